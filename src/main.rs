//! The `pointshade` binary: see [`pointshade::cli`].

fn main() -> std::process::ExitCode {
    pointshade::cli::main()
}
