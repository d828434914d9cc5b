//! The documentation's examples, run: every fenced block of README.md and docs/*.md whose info
//! string is `sh example` (commands) or `toml example` (a scene file), so that a documented
//! example cannot rot.
//!
//! - A command line starts with `pointshade` or `cargo run --release --`; it runs this build's
//!   binary from the repository root, with paths under `out/` moved to a temporary folder and,
//!   for `render` and `bake` without `--width`, `--height` or `--crop`, a 32×24 image at 1 spp.
//!   `#` starts a comment; a line may end in `\` to continue. It must exit 0.
//! - A scene file is written to a temporary folder, its `meshes/` and `../shared/` paths taken
//!   from the repository root, and rendered (or shaded, with a `[normal_map]` section) likewise.
//!   It must exit 0 without a warning.
//!
//! Blocks that name `../shared/` need the shared test data: they run in their own test, ignored
//! without it.

use std::path::{Path, PathBuf};

use crate::support::{self, Scratch};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// (file, first line, kind, text) of every marked block.
fn blocks() -> Vec<(PathBuf, usize, &'static str, String)> {
    let mut files = vec![root().join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    files.extend(docs);
    let mut out = Vec::new();
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        let mut open: Option<(usize, &'static str, String)> = None;
        for (n, line) in text.lines().enumerate() {
            match (&mut open, line.trim_start()) {
                (None, fence) if fence.starts_with("```") => {
                    let kind = match fence.trim_start_matches('`').trim() {
                        "sh example" => "sh",
                        "toml example" => "toml",
                        _ => "other",
                    };
                    open = Some((n + 2, kind, String::new()));
                }
                (Some(_), fence) if fence.starts_with("```") => {
                    let (first, kind, body) = open.take().unwrap();
                    if kind != "other" {
                        out.push((file.clone(), first, kind, body));
                    }
                }
                (Some((_, _, body)), _) => {
                    body.push_str(line);
                    body.push('\n');
                }
                (None, _) => {}
            }
        }
        assert!(open.is_none(), "{}: a fenced block is not closed", file.display());
    }
    out
}

/// Runs `args` (a command of the docs) from the repository root; `out` replaces `out/`. Returns
/// its standard error.
fn run(args: &[String], out: &Path, what: &str) -> String {
    let words: Vec<String> = args
        .iter()
        .map(|a| a.replace("out/", &format!("{}/", out.display())))
        .collect();
    let mut rest: &[String] = &words;
    if rest.first().map(String::as_str) == Some("pointshade") {
        rest = &rest[1..];
    } else if rest.len() >= 3 && rest[..3] == ["cargo", "run", "--release"] {
        rest = &rest[3..];
        if rest.first().map(String::as_str) == Some("--") {
            rest = &rest[1..];
        }
    } else {
        panic!("{what}: a command of an example starts with `pointshade` or `cargo run --release --`");
    }
    let mut extra: Vec<&str> = Vec::new();
    let given = |flag: &str| rest.iter().any(|w| w == flag);
    if matches!(rest.first().map(String::as_str), Some("render" | "bake")) && !given("--crop") {
        if !given("--width") && !given("--height") {
            extra.extend(["--width", "32", "--height", "24"]);
        }
        if rest[0] == "render" && !given("--spp") && !given("--time-budget") {
            extra.extend(["--spp", "1"]);
        }
    }
    let r = support::command()
        .current_dir(root())
        .args(rest)
        .args(&extra)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&r.stderr).to_string();
    assert!(r.status.success(), "{what}: `{}` failed:\n{stderr}", words.join(" "));
    stderr
}

/// The command lines of an `sh example` block, continuations joined and comments dropped.
fn commands(body: &str) -> Vec<Vec<String>> {
    let joined = body.replace("\\\n", " ");
    joined
        .lines()
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .filter(|l| !l.is_empty())
        .map(|l| l.split_whitespace().map(str::to_string).collect())
        .collect()
}

fn run_blocks(shared: bool) -> usize {
    let mut ran = 0;
    for (i, (file, line, kind, body)) in blocks().into_iter().enumerate() {
        if body.contains("../shared/") != shared {
            continue;
        }
        let what = format!("{}:{line}", file.strip_prefix(root()).unwrap_or(&file).display());
        let out = Scratch::new(&format!("example-{shared}-{i}"));
        match kind {
            "sh" => {
                for command in commands(&body) {
                    run(&command, &out, &what);
                }
            }
            _ => {
                let repo = root().display().to_string();
                let scene = body
                    .replace("\"meshes/", &format!("\"{repo}/meshes/"))
                    .replace("\"../shared/", &format!("\"{repo}/../shared/"));
                let path = out.join("example.toml");
                std::fs::write(&path, scene).unwrap();
                let command = if body.contains("[normal_map]") {
                    "normalmap"
                } else {
                    "render"
                };
                let args = [
                    "pointshade",
                    command,
                    &path.display().to_string(),
                    "-o",
                    "out/example.png",
                ]
                .map(str::to_string);
                let stderr = run(&args, &out, &what);
                assert!(!stderr.contains("warning"), "{what}: the example warns:\n{stderr}");
            }
        }
        ran += 1;
    }
    ran
}

#[test]
fn the_documented_examples_run_from_a_fresh_clone() {
    let ran = run_blocks(false);
    assert!(
        ran >= 4,
        "only {ran} example blocks found: are the fences marked `sh example`?"
    );
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn the_documented_examples_with_the_shared_data_run() {
    let ran = run_blocks(true);
    assert!(ran >= 2, "only {ran} example blocks that use ../shared found");
}
