//! `host-sim`: the lugre-servo command-line tool. Each subcommand lives in `cli/`, with its
//! own arguments; this file parses and dispatches, and prints a refusal as `error: ...`.

use clap::{Parser, Subcommand};
use std::process::ExitCode;

mod cli;

#[derive(Parser)]
#[command(
    name = "host-sim",
    version,
    about = "Electro-hydraulic servo axis simulator and LuGre friction tools"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// The whole story on the simulated Table 2 cylinder (writes into --out).
    Demo(cli::demo::Args),
    /// Identifies the LuGre parameters (static and dynamic stage) with a genetic algorithm or
    /// CMA-ES, on simulated experiments or measured records.
    Identify(cli::identify::Args),
    /// Closed-loop tracking benchmark: the core's controller against the simulator.
    Track(cli::track::Args),
    /// Compares a friction model with a measured record, finds where it fails and which
    /// physical effect is missing, adds effects and reports the error falling.
    Diagnose(cli::diagnose::Args),
    /// Runs one experiment on the simulated axis and writes the record as CSV.
    Simulate(cli::simulate::Args),
    /// Processor-in-the-loop: the firmware in QEMU controls the simulated axis over the
    /// emulated USART; compared with the same controller on the host.
    Pil(cli::pil::Args),
}

fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::Demo(a) => cli::demo::run(&a),
        Command::Identify(a) => cli::identify::run(&a),
        Command::Track(a) => cli::track::run(&a),
        Command::Diagnose(a) => cli::diagnose::run(&a),
        Command::Simulate(a) => cli::simulate::run(&a),
        Command::Pil(a) => cli::pil::run(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
