//! The `shadowtruth` command; everything it does is in the crate's library (`src/lib.rs`).

fn main() -> std::process::ExitCode {
    shadowtruth_cli::main()
}
