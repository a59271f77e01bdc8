//! `sim-host`: plan, learn, simulate and inspect reactive behavior trees.
//!
//! Run without arguments for the blended planning-and-acting demo; `sim-host --help`
//! lists the subcommands.
#![forbid(unsafe_code)]
// Every write goes through `cli::output`, which returns errors; `print!` panics.
#![deny(clippy::print_stdout, clippy::print_stderr)]

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}
