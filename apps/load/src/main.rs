//! The `gymfleet-load` binary: parses the command line, runs the load, prints the table
//! on stdout. Exit status 2 for a bad command line, 1 for a failed run.

use std::process::ExitCode;

use clap::Parser;
use gymfleet_load::{render_table, run, Cli};

fn main() -> ExitCode {
    let outcome = Cli::parse().resolve().and_then(|config| run(&config));
    match outcome {
        Ok(report) => {
            print!("{}", render_table(&report));
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("gymfleet-load: error: {e}");
            ExitCode::from(if e.is_usage() { 2 } else { 1 })
        }
    }
}
