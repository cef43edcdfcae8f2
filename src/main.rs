//! The `shadowtruth` command; everything it does is in the library (`src/cli.rs`).

fn main() -> std::process::ExitCode {
    shadowtruth::run_cli()
}
