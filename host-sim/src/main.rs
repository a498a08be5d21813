//! `picomis-sim`: see `picomis-sim --help` and the crate docs.

use std::process::ExitCode;

use clap::Parser;
use picomis_sim::cli::{Cli, run};

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code() as u8)
        }
    }
}
