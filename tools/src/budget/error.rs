//! Why a budget command failed.

use std::fmt;
use std::io;
use std::path::PathBuf;

/// A budget command's failure (printed as one line, exit status 1).
#[derive(Debug)]
pub enum Error {
    /// A file could not be read or written.
    Io { path: PathBuf, source: io::Error },
    /// budget.json is not a JSON object.
    Json { path: PathBuf, source: serde_json::Error },
    /// A line of a figures file is not `key value` with a number.
    NotAFigure { path: PathBuf, line: usize, text: String },
    /// A figure the command needs is not in the file.
    MissingFigure { path: PathBuf, key: String },
    /// docs/firmware.md lacks a marker line of the generated block.
    NoMarker { path: PathBuf, marker: &'static str },
    /// `readme --check`: the committed table is not the one budget.json generates.
    TableDiffers,
    /// `check`: a figure rose more than the tolerance, or crossed its target.
    OverBudget,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Error::Json { path, source } => write!(f, "{}: {source}", path.display()),
            Error::NotAFigure { path, line, text } => {
                write!(f, "{}:{line}: not a figure (\"key value\"): {text}", path.display())
            }
            Error::MissingFigure { path, key } => write!(f, "{}: no figure {key}", path.display()),
            Error::NoMarker { path, marker } => write!(f, "{} has no line: {marker}", path.display()),
            Error::TableDiffers => f.write_str(
                "the firmware table of docs/firmware.md differs from firmware/budget.json: run scripts/budget.sh readme",
            ),
            Error::OverBudget => f.write_str(
                "over budget (a deliberate change: scripts/firmware.sh measure, and commit firmware/budget.json)",
            ),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Io { source, .. } => Some(source),
            Error::Json { source, .. } => Some(source),
            _ => None,
        }
    }
}
