//! What every subcommand shares: errors naming an option, the workers, comma lists.

use pointshade::error::InputError;

/// An error about a command-line option rather than a file.
pub(crate) fn option_error(option: &str, problem: impl std::fmt::Display) -> InputError {
    InputError::new(option, problem)
}

/// The workers of a command's `--threads` (rayon's global pool of all cores when absent).
/// Everything parallel, loading included, runs inside them, so the option bounds the whole command.
pub(crate) fn workers(threads: Option<usize>) -> Result<pointshade::render::Workers, InputError> {
    pointshade::render::Workers::new(threads).map_err(|e| option_error("--threads", e))
}

/// The comma-separated values of `option` (`text`), each read by `parse`; an error naming the
/// option and what it expects (`expected`) if any is not one.
pub(crate) fn comma_list<T>(
    option: &str,
    text: &str,
    expected: &str,
    parse: impl Fn(&str) -> Option<T>,
) -> Result<Vec<T>, InputError> {
    text.split(',')
        .map(|s| parse(s.trim()))
        .collect::<Option<Vec<T>>>()
        .ok_or_else(|| option_error(option, format!("expected {expected}, got '{text}'")))
}
