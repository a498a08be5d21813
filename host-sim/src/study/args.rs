//! What `picomis-sim study` is asked for, and what follows from it: the ladder of samples per
//! pixel, the reference's samples, the study film.

use std::path::PathBuf;

use picomis::Film;
use picomis_format::IntegratorDesc;

use crate::SimError;

/// `picomis-sim study`.
#[derive(Debug, Clone, clap::Args)]
pub struct StudyArgs {
    /// A picomis-scene/1 JSON file or the name of a built-in scene (default: every built-in scene).
    pub scene: Option<String>,
    /// Output folder (created if missing); the reference cache goes to DIR/cache.
    #[arg(long, value_name = "DIR", default_value = "study-out")]
    pub out: PathBuf,
    /// Largest samples per pixel of the ladder 1, 2, 4, ... (a last rung at N if N is not a power of two).
    #[arg(long, value_name = "N", default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub max_spp: u32,
    /// Seeds per rung (the spread across seeds is drawn as a band).
    #[arg(long, value_name = "K", default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub seeds: u32,
    /// Film scale (default: each scene's film scaled down to at most 192 x 128 pixels' worth).
    #[arg(long, value_name = "F")]
    pub scale: Option<f32>,
    /// Samples per pixel of the reference (default: the larger of 1024 and 32 x --max-spp).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(2..=10_000_000))]
    pub ref_spp: Option<u32>,
    /// Mitsuba 3 reference of the Veach scene (default: the one built into picomis-sim, from
    /// host-sim/tests/data/veach_mis.ref.exr).
    #[arg(long, value_name = "FILE.exr")]
    pub mitsuba_ref: Option<PathBuf>,
    /// Measure the error of the full radiance (lights seen directly included).
    #[arg(long)]
    pub include_emitted: bool,
    /// The integrator of the "defaults" method: every key of a scene file's integrator block, as
    /// a flag, over each scene's block (the other methods are the study's own).
    #[command(flatten)]
    pub integrator: IntegratorDesc,
}

/// Pixels of the default study film: 192 x 128 (the Veach film at half size).
const STUDY_PIXELS: f64 = 192.0 * 128.0;

/// Seeds of the ladder renders are `LADDER_SEED + k`; the reference and the equal-time renders
/// use other seeds, so no render shares random numbers with the reference.
pub const LADDER_SEED: u32 = 1;
/// Seed of the equal-time renders.
pub const EQUAL_TIME_SEED: u32 = 0x00e9_0000;

impl StudyArgs {
    /// `--scale`, if it is in (0, 4].
    pub fn check(&self) -> Result<(), SimError> {
        match self.scale {
            Some(s) if !(s.is_finite() && s > 0.0 && s <= 4.0) => {
                Err(SimError::Usage(format!("--scale {s}: expected a number in (0, 4]")))
            }
            _ => Ok(()),
        }
    }

    /// The rungs of the ladder: [`ladder`] up to `--max-spp`.
    pub fn ladder(&self) -> Vec<u32> {
        ladder(self.max_spp)
    }

    /// The seeds of each rung.
    pub fn ladder_seeds(&self) -> Vec<u32> {
        (0..self.seeds).map(|k| LADDER_SEED + k).collect()
    }

    /// Samples per pixel of the reference: `--ref-spp`, by default the larger of 1024 and
    /// 32 x `--max-spp`.
    pub fn reference_spp(&self) -> u32 {
        self.ref_spp.unwrap_or_else(|| (32 * self.max_spp).max(1024))
    }

    /// The study film of a scene whose own film is `film` (see [`study_film`]).
    pub fn film(&self, film: Film) -> Result<Film, SimError> {
        study_film(film, self.scale)
    }
}

/// 1, 2, 4, ... up to `max` (and `max` itself).
pub fn ladder(max: u32) -> Vec<u32> {
    let mut v: Vec<u32> =
        std::iter::successors(Some(1u32), |&s| s.checked_mul(2)).take_while(|&s| s <= max).collect();
    if v.last() != Some(&max) {
        v.push(max);
    }
    v
}

/// The study film: `scale` times the scene's film, or by default the film scaled down to at most
/// 192 x 128 pixels' worth (`STUDY_PIXELS`).
pub fn study_film(film: Film, scale: Option<f32>) -> Result<Film, SimError> {
    let (w, h) = (f64::from(film.width()), f64::from(film.height()));
    let s = match scale {
        Some(s) => f64::from(s),
        None => (STUDY_PIXELS / (w * h)).sqrt().min(1.0),
    };
    let (sw, sh) = (((w * s).round() as u32).max(1), ((h * s).round() as u32).max(1));
    Film::new(sw, sh).map_err(|e| SimError::Usage(format!("--scale: film {sw}x{sh}: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ladders_and_films() {
        assert_eq!(ladder(1), vec![1]);
        assert_eq!(ladder(8), vec![1, 2, 4, 8]);
        assert_eq!(ladder(12), vec![1, 2, 4, 8, 12]);
        let f = study_film(Film::new(384, 256).unwrap(), None).unwrap();
        assert_eq!((f.width(), f.height()), (192, 128));
        let f = study_film(Film::new(64, 48).unwrap(), None).unwrap();
        assert_eq!((f.width(), f.height()), (64, 48));
        let f = study_film(Film::new(64, 48).unwrap(), Some(0.5)).unwrap();
        assert_eq!((f.width(), f.height()), (32, 24));
    }
}
