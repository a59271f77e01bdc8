//! The command line: one module per subcommand, each with its clap `Args` and a `run`.
//!
//! Every failure is one line on stderr, `error: <what> (<where>)`, and exit code 2;
//! clap's own argument errors also exit with 2 ([`message::one_line`] keeps each one
//! line). Everything written goes through [`output`], which returns every write's error:
//! no `print!` here (clippy's `print_stdout` and `print_stderr` are denied), so a closed
//! or full stdout is an error, never a panic.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod bench_pddl;
mod blend;
mod btlog;
mod catalog;
mod catalogs;
mod deploy;
mod export;
mod groot2;
mod import;
mod inspect;
mod learn;
mod link;
mod message;
mod monitor;
pub mod output;
mod plan;
mod plot;
mod run;
mod run_strips;
mod scenario;
mod watch;

/// Reactive behavior trees, planned and learned on the host, shipped to a controller.
#[derive(Parser, Debug)]
#[command(
    name = "sim-host",
    version,
    about = "Plan, learn, simulate and inspect reactive behavior trees",
    long_about = "Plan, learn, simulate and inspect reactive behavior trees.\n\n\
                  Without a subcommand, runs the blended planning-and-acting demo of \
                  Colledanchise et al. (ICRA 2019)."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Load and validate a tree image; print the tree and the image's facts.
    Inspect(inspect::Args),
    /// Write a tree image as ASCII, tokens, Graphviz DOT or BehaviorTree.CPP XML.
    Export(export::Args),
    /// Import a BehaviorTree.CPP XML tree (Groot2, Nav2) as an image or another notation.
    #[command(long_about = import::LONG_ABOUT)]
    Import(import::Args),
    /// Turn a controller's trace into a Groot2 replay log (.btlog).
    #[command(long_about = btlog::LONG_ABOUT)]
    Btlog(btlog::Args),
    /// Print the behavior set of BehaviorTree.CPP models, or the Rust table a controller compiles in.
    #[command(long_about = catalog::LONG_ABOUT)]
    Catalog(catalog::Args),
    /// Plan a tree by backchaining (Colledanchise et al. 2019) from PDDL or for a brick task.
    #[command(long_about = plan::LONG_ABOUT)]
    Plan(plan::Args),
    /// Run one episode of a tree on a brick task; print the outcome and the fitness.
    #[command(long_about = run::LONG_ABOUT)]
    Run(run::Args),
    /// Run a scenario of the papers, narrated tick by tick (`--list` shows them).
    #[command(long_about = scenario::LONG_ABOUT)]
    Scenario(scenario::Args),
    /// Learn trees with the GP of Styrud et al. (brick tasks or a PDDL problem); one folder per run.
    #[command(long_about = learn::LONG_ABOUT)]
    Learn(learn::Args),
    /// Draw learning curves (PNG) and a results table from `learn`'s run folders.
    #[command(long_about = plot::LONG_ABOUT)]
    Plot(plot::Args),
    /// Send a tree image to a running controller; it swaps it in between two ticks.
    Deploy(deploy::Args),
    /// Watch a running controller's tree live, status by status.
    Monitor(monitor::Args),
    /// Serve a running controller's tree to Groot2, live, across hot swaps.
    Groot2(groot2::Args),
    /// Blended planning and acting on a controller: the tree grows from the goal while it acts.
    #[command(long_about = blend::LONG_ABOUT)]
    Blend(blend::Args),
    /// Measure the planner on a folder of PDDL benchmarks, side by side with pyperplan.
    #[command(long_about = bench_pddl::LONG_ABOUT)]
    BenchPddl(bench_pddl::Args),
}

/// Parses the command line, runs it, and turns any error into one line and exit code 2.
/// A broken pipe on an output (the reader went away, as with `| head`) ends the program
/// quietly with exit code 0.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        // --help, --version: to stdout, exit 0.
        Err(e) if !e.use_stderr() => {
            let printed = e.print().and_then(|()| std::io::Write::flush(&mut std::io::stdout()));
            return match printed {
                Ok(()) => ExitCode::SUCCESS,
                Err(io) if io.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
                Err(io) => fail(&format!("error: {}", output::WriteError::io("stdout", &io))),
            };
        }
        Err(e) => return fail(&clap_line(&e)),
    };
    let result = match cli.command {
        None => scenario::demo(),
        Some(Command::Inspect(args)) => inspect::run(&args),
        Some(Command::Export(args)) => export::run(&args),
        Some(Command::Import(args)) => import::run(&args),
        Some(Command::Catalog(args)) => catalog::run(&args),
        Some(Command::Btlog(args)) => btlog::run(&args),
        Some(Command::Plan(args)) => plan::run(&args),
        Some(Command::Run(args)) => run::run(&args),
        Some(Command::Scenario(args)) => scenario::run(&args),
        Some(Command::Learn(args)) => learn::run(&args),
        Some(Command::Plot(args)) => plot::run(&args),
        Some(Command::Deploy(args)) => deploy::run(&args),
        Some(Command::Monitor(args)) => monitor::run(&args),
        Some(Command::Groot2(args)) => groot2::run(&args),
        Some(Command::Blend(args)) => blend::run(&args),
        Some(Command::BenchPddl(args)) => bench_pddl::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => fail(&format!("error: {}", message::chain(&e))),
    }
}

/// Whether the error is a write to a pipe whose reader went away.
fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| c.downcast_ref::<output::WriteError>().is_some_and(output::WriteError::is_broken_pipe))
}

/// Prints `line` as one clean line on stderr and returns exit code 2 (also when stderr
/// itself cannot be written: there is nowhere left to say so).
fn fail(line: &str) -> ExitCode {
    let _ = output::stderr(format!("{}\n", message::one_line(line)).as_bytes());
    ExitCode::from(2)
}

/// A clap error as one line: its first paragraph (the message and, for bad values, the
/// possible ones), without the usage and the `--help` tip.
fn clap_line(e: &clap::Error) -> String {
    let text = e.render().to_string();
    let first = text.split("\n\n").next().unwrap_or("");
    let line: Vec<&str> = first.lines().map(str::trim).filter(|l| !l.is_empty()).collect();
    line.join(" ")
}
