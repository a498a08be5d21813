//! The firmware's figures: one committed file (firmware/budget.json), the table of
//! docs/firmware.md generated from it, and the budget check. scripts/budget.sh calls these
//! commands (from `scripts/firmware.sh measure` and `budget`, and the test command); nothing else
//! writes the file or the table.

mod check;
mod error;
mod figures;
mod keys;
mod readme;
mod table;

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use clap::Subcommand;

pub use error::Error;
use figures::Figures;

/// The budget commands.
#[derive(Subcommand)]
pub enum Command {
    /// FIGURES ("key value" lines, from scripts/firmware.sh) -> firmware/budget.json.
    Write {
        /// The figures file.
        figures: PathBuf,
    },
    /// Prints the generated block of docs/firmware.md (from firmware/budget.json).
    Table,
    /// Rewrites the table of docs/firmware.md between its markers.
    Readme {
        /// Fails (showing the difference) if that table differs from firmware/budget.json
        /// instead.
        #[arg(long)]
        check: bool,
    },
    /// Fails if instructions per camera sample (f32 and fixed-point builds, lecture and best
    /// settings), flash text, static RAM or peak stack exceed firmware/budget.json by more than
    /// 2 %, or a figure within its stated target crosses it.
    Check {
        /// The figures file.
        figures: PathBuf,
    },
}

/// Runs `command` on the workspace at `root`.
pub fn run(root: &Path, command: Command) -> Result<(), Error> {
    let budget_path = root.join("firmware/budget.json");
    let doc_path = root.join("docs/firmware.md");
    let budget = || Figures::from_budget_json(&budget_path, &read(&budget_path)?);
    match command {
        Command::Write { figures } => {
            let json = figures::budget_json(&Figures::from_lines(&figures, &read(&figures)?)?)?;
            replace(&budget_path, &json)?;
            println!("wrote {}", budget_path.display());
        }
        Command::Table => print!("{}", table::block(&budget()?)?),
        Command::Readme { check } => {
            let doc = read(&doc_path)?;
            let new = readme::with_block(&doc, &table::block(&budget()?)?)
                .map_err(|marker| Error::NoMarker { path: doc_path.clone(), marker })?;
            if check {
                if new != doc {
                    let generated = format!("{} (generated from firmware/budget.json)", doc_path.display());
                    print!("{}", readme::diff(&doc, &new, &doc_path.display().to_string(), &generated));
                    return Err(Error::TableDiffers);
                }
                println!("docs/firmware.md firmware table == firmware/budget.json");
            } else {
                replace(&doc_path, &new)?;
                println!("rewrote the firmware table in {}", doc_path.display());
            }
        }
        Command::Check { figures } => {
            let measured = Figures::from_lines(&figures, &read(&figures)?)?;
            check::check(&budget()?, &measured, &mut io::stdout().lock())?;
        }
    }
    Ok(())
}

fn read(path: &Path) -> Result<String, Error> {
    fs::read_to_string(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })
}

/// Writes `text` to `path` through a temporary file beside it, so that a reader never sees half.
fn replace(path: &Path, text: &str) -> Result<(), Error> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    fs::write(&tmp, text).map_err(|source| Error::Io { path: tmp.clone(), source })?;
    fs::rename(&tmp, path).map_err(|source| Error::Io { path: path.to_path_buf(), source })
}
