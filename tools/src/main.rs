//! `picomis-tools`: the workspace's own tools, in Rust (the xtask pattern; `cargo xtask ...` is
//! an alias for it). The shell scripts under `scripts/` orchestrate; the logic and its tests are
//! here.
//!
//! ```text
//! picomis-tools budget write FIGURES     FIGURES ("key value" lines) -> firmware/budget.json
//! picomis-tools budget table             prints the table block of docs/firmware.md
//! picomis-tools budget readme [--check]  rewrites (or checks) that block in docs/firmware.md
//! picomis-tools budget check FIGURES     fails if FIGURES exceed firmware/budget.json
//! ```

mod budget;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(name = "picomis-tools", about = "The picomis workspace's own tools")]
struct Cli {
    /// The workspace root (default: the workspace this tool was built from).
    #[arg(long, global = true, value_name = "DIR")]
    root: Option<PathBuf>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// The firmware's figures: firmware/budget.json, the table of docs/firmware.md generated from
    /// it, and the budget check (scripts/budget.sh calls this).
    #[command(subcommand)]
    Budget(budget::Command),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let root = cli.root.unwrap_or_else(built_root);
    match cli.command {
        Command::Budget(command) => match budget::run(&root, command) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("picomis-tools budget: {e}");
                ExitCode::FAILURE
            }
        },
    }
}

/// The workspace root this tool was built from (the parent of `tools/`).
fn built_root() -> PathBuf {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest.parent().unwrap_or(manifest).to_path_buf()
}
