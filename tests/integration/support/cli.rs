//! Running this build's `pointshade` binary, and the contract every refusal of bad input keeps.

use std::ffi::OsStr;
use std::path::Path;
use std::process::{Command, Output};

/// A command for this build's binary (Cargo builds it for the integration tests), for a test
/// that sets the working folder or the environment, or builds its arguments step by step.
pub fn command() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pointshade"))
}

/// Runs this build's binary with `args` and waits for it: its exit status, stdout and stderr.
pub fn pointshade<S: AsRef<OsStr>>(args: &[S]) -> Output {
    command().args(args).output().expect("the pointshade binary runs")
}

/// The failure contract for bad input: exit code 2; exactly one `error:` line on stderr, which
/// mentions each of `must_mention`; no panic; none of `must_not_exist` written, and no `*.tmp`
/// file left in their folders (an atomic write that was begun is cleaned up). Returns the error
/// line. Other lines (warnings about the input) may come before it.
#[track_caller]
pub fn assert_input_error(output: &Output, must_mention: &[&str], must_not_exist: &[&Path]) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "exit code: {stderr}");
    assert!(!stderr.contains("panicked"), "a panic: {stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "exactly one error line: {stderr}");
    for word in must_mention {
        assert!(errors[0].contains(word), "'{}' should mention '{word}'", errors[0]);
    }
    for path in must_not_exist {
        assert!(!path.exists(), "{} was written after an error", path.display());
        let Some(folder) = path.parent().filter(|f| f.is_dir()) else {
            continue;
        };
        let leftovers: Vec<_> = std::fs::read_dir(folder)
            .unwrap()
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|name| name.ends_with(".tmp"))
            .collect();
        assert!(leftovers.is_empty(), "temporary files left behind: {leftovers:?}");
    }
    errors[0].to_string()
}

/// [`assert_input_error`], and the error line is all there is on stderr (no warning, no
/// progress): for commands that refuse their arguments before reading any input.
#[track_caller]
pub fn assert_one_line_error(output: &Output, must_mention: &[&str], must_not_exist: &[&Path]) -> String {
    let error = assert_input_error(output, must_mention, must_not_exist);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(stderr.trim_end(), error, "one line on stderr: {stderr}");
    error
}
