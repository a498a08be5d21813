//! Memory: the bytes a command's buffers need, and what the machine has. A render whose
//! buffers would not fit is refused before it allocates, with one line (exit code 2), instead of
//! failing halfway (a 16384 x 16384 film needs some 20 GB).
//!
//! The limit is the `PICOMIS_MEMORY_LIMIT` environment variable (bytes) when it is set, else
//! the kernel's estimate of the memory available without swapping (`MemAvailable` in
//! `/proc/meminfo`); where neither is known (not Linux), nothing is refused.

use std::mem::size_of;

use picomis::{Estimate, Film, Rgb};

use crate::SimError;
use crate::output::Format;

/// The environment variable that overrides the memory limit, in bytes.
pub const LIMIT_VAR: &str = "PICOMIS_MEMORY_LIMIT";

/// Where the limit came from (named in the refusal, so that the reader knows what to change).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// [`LIMIT_VAR`].
    Variable,
    /// `MemAvailable` in `/proc/meminfo`.
    MemAvailable,
}

/// The memory a command may use, in bytes, and where that number came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limit {
    /// Bytes.
    pub bytes: u64,
    /// Its source.
    pub source: Source,
}

impl Limit {
    /// The limit of this process: [`LIMIT_VAR`] when set (an error when it is not a number of
    /// bytes), else `MemAvailable`; `None` when neither is known.
    pub fn of_machine() -> Result<Option<Limit>, SimError> {
        if let Some(v) = std::env::var_os(LIMIT_VAR) {
            let text = v.to_string_lossy();
            let bytes = text
                .trim()
                .parse::<u64>()
                .map_err(|_| SimError::Usage(format!("{LIMIT_VAR}={text}: expected a number of bytes")))?;
            return Ok(Some(Limit { bytes, source: Source::Variable }));
        }
        let meminfo = std::fs::read_to_string("/proc/meminfo").ok();
        Ok(meminfo
            .as_deref()
            .and_then(mem_available)
            .map(|bytes| Limit { bytes, source: Source::MemAvailable }))
    }

    /// Refuses `need` bytes for `what` when they exceed the limit: one line, naming the need,
    /// the limit and its source.
    pub fn check(&self, what: &str, need: u64) -> Result<(), SimError> {
        if need <= self.bytes {
            return Ok(());
        }
        let source = match self.source {
            Source::Variable => format!("the limit {LIMIT_VAR} sets"),
            Source::MemAvailable => format!("available (MemAvailable; {LIMIT_VAR}=BYTES overrides)"),
        };
        Err(SimError::Usage(format!(
            "{what} needs about {} of memory, more than the {} {source}",
            human(need),
            human(self.bytes)
        )))
    }
}

/// Refuses `need` bytes for `what` when they exceed this machine's [`Limit`].
pub fn check(what: &str, need: u64) -> Result<(), SimError> {
    match Limit::of_machine()? {
        Some(limit) => limit.check(what, need),
        None => Ok(()),
    }
}

/// `MemAvailable` of a `/proc/meminfo` text, in bytes.
pub fn mem_available(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let mut fields = line["MemAvailable:".len()..].split_whitespace();
    let value: u64 = fields.next()?.parse().ok()?;
    match fields.next() {
        Some("kB") => value.checked_mul(1024),
        None => Some(value),
        Some(_) => None,
    }
}

/// Bytes per pixel of one render's estimates (the kernel's [`Estimate`]: radiance split by
/// technique, with weights and counts).
pub const ESTIMATE_BYTES: u64 = size_of::<Estimate>() as u64;

/// Bytes per pixel of a linear image ([`crate::output::Image`]).
pub const IMAGE_BYTES: u64 = size_of::<Rgb>() as u64;

/// The bytes `picomis-sim render` allocates for `film` written as `format`: the estimates, the
/// linear image and the encoder's buffers ([`Format::encoding_bytes_per_pixel`]).
pub fn render_bytes(film: Film, format: Format) -> u64 {
    u64::from(film.pixels()) * (ESTIMATE_BYTES + IMAGE_BYTES + format.encoding_bytes_per_pixel())
}

/// The bytes `picomis-sim figure` allocates for `renders` renders of `film`: their estimates,
/// and a canvas of at least `panels` panels of 8-bit RGB (upscaled films are small) with its PNG
/// encoding.
pub fn figure_bytes(film: Film, renders: u64, panels: u64) -> u64 {
    let pixels = u64::from(film.pixels());
    pixels * (renders * ESTIMATE_BYTES + panels * (3 + Format::Png.encoding_bytes_per_pixel()))
}

/// `bytes` for people: `1.5 GB`, `12.0 MB`, `512 bytes`.
pub fn human(bytes: u64) -> String {
    const UNITS: [(&str, f64); 3] = [("GB", 1e9), ("MB", 1e6), ("kB", 1e3)];
    let b = bytes as f64;
    UNITS
        .iter()
        .find(|(_, size)| b >= *size)
        .map_or_else(|| format!("{bytes} bytes"), |(unit, size)| format!("{:.1} {unit}", b / size))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_mem_available() {
        let text = "MemTotal:       16318508 kB\nMemFree:          402640 kB\nMemAvailable:    7412300 kB\n";
        assert_eq!(mem_available(text), Some(7_412_300 * 1024));
        assert_eq!(mem_available("MemTotal: 1 kB\n"), None);
        assert_eq!(mem_available("MemAvailable: lots\n"), None);
    }

    #[test]
    fn refuses_what_exceeds_the_limit() {
        let limit = Limit { bytes: 1000, source: Source::Variable };
        assert!(limit.check("x", 1000).is_ok());
        let e = limit.check("a 20x20 render", 1001).unwrap_err().to_string();
        assert_eq!(
            e,
            "a 20x20 render needs about 1.0 kB of memory, more than the 1.0 kB the limit PICOMIS_MEMORY_LIMIT sets"
        );
        let film = Film::new(16384, 16384).unwrap();
        // The example: some 20 GB, whatever the format.
        for format in [Format::Png, Format::Exr, Format::Pfm, Format::Rgb565] {
            assert!(render_bytes(film, format) > 16_000_000_000, "{format:?}");
        }
    }

    #[test]
    fn sizes_for_people() {
        assert_eq!(human(512), "512 bytes");
        assert_eq!(human(12_000_000), "12.0 MB");
        assert_eq!(human(17_179_869_184), "17.2 GB");
    }
}
