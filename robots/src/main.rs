//! `robid`: robot dynamic model identification from the command line.

mod cli;

fn main() -> std::process::ExitCode {
    cli::run()
}
