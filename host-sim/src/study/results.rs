//! What the study measures on one scene ([`SceneStudy`]: the ladder's [`Record`]s, the
//! [`EqualTime`] renders, the reference and the regions), and the questions the reports ask of
//! it: which method is which, the rungs, means over seeds, the cost per sample.

use picomis::{Arith, Heuristic, Method, Rgb, SphereSampling};
use picomis_host::study::Extras;

use super::methods::methods;
use super::metrics::ErrorStats;
use super::reference::Reference;
use super::regions::{RegionMap, RegionStudy};

/// One timed render of the ladder.
#[derive(Clone, Debug)]
pub struct Record {
    /// Index in [`methods`].
    pub method: usize,
    /// Samples per pixel.
    pub spp: u32,
    /// Seed.
    pub seed: u32,
    /// Wall-clock seconds on all cores.
    pub seconds: f64,
    /// Error against the study's reference.
    pub error: ErrorStats,
    /// Error of the full radiance against the Mitsuba 3 reference (Veach scene).
    pub mitsuba: Option<ErrorStats>,
    /// For a method whose ray queries are not f32: its error against its f32 twin
    /// ([`f32_twin`]) rendered with the same seed and spp (the same random numbers).
    pub vs_f32: Option<ErrorStats>,
}

/// A method that the scene's arithmetic cannot run: no renders, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Rejected {
    /// Index in [`methods`].
    pub method: usize,
    /// The scene's error, naming the entry.
    pub reason: String,
}

/// One render of the equal-time comparison.
#[derive(Clone, Debug)]
pub struct EqualTime {
    /// Index in [`methods`].
    pub method: usize,
    /// Samples per pixel chosen from the method's measured cost.
    pub spp: u32,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// Error against the study's reference.
    pub error: ErrorStats,
    /// The image (full radiance).
    pub image: Vec<Rgb>,
}

/// Everything measured on one scene.
#[derive(Clone, Debug)]
pub struct SceneStudy {
    /// Scene name.
    pub name: String,
    /// Study film.
    pub width: u32,
    /// Study film.
    pub height: u32,
    /// Ladder renders.
    pub records: Vec<Record>,
    /// Equal-time renders.
    pub equal_time: Vec<EqualTime>,
    /// The time budget of the equal-time renders.
    pub budget: f64,
    /// The reference.
    pub reference: Reference,
    /// Plate x light regions, when the scene has them (the Veach scene).
    pub regions: Option<RegionMap>,
    /// Errors per region, each light rendered alone at the top rung.
    pub region_study: RegionStudy,
    /// Why there is no Mitsuba comparison (Veach scene only), if there is none.
    pub mitsuba_note: Option<String>,
    /// Error of the reference's full radiance against the Mitsuba 3 reference (Veach scene).
    pub reference_vs_mitsuba: Option<ErrorStats>,
    /// The methods the scene rejected (fixed point cannot represent it).
    pub rejected: Vec<Rejected>,
}

impl SceneStudy {
    /// Why method `mi` was not run on this scene, if it was not.
    pub fn rejection(&self, mi: usize) -> Option<&str> {
        self.rejected.iter().find(|r| r.method == mi).map(|r| r.reason.as_str())
    }
}

/// Index in [`methods`] of `method` with sphere lights sampled by `spheres`, the default
/// sample stream and uniform light selection (0 if absent).
pub fn index_of(method: Method, spheres: SphereSampling) -> usize {
    methods()
        .iter()
        .position(|m| m.method == method && m.spheres == spheres && m.extras == Extras::default())
        .unwrap_or(0)
}

/// Index in [`methods`] of the f32 twin of method `mi` (the same method and options with
/// the ray queries in f32), for a method whose ray queries are not f32; `None` for the others.
pub fn f32_twin(mi: usize) -> Option<usize> {
    let methods = methods();
    let m = methods.get(mi)?;
    if m.extras.arith == Arith::F32 {
        return None;
    }
    methods
        .iter()
        .position(|o| o.method == m.method && o.spheres == m.spheres && o.extras == m.extras.in_f32())
}

/// Index of the balance heuristic in [`methods`] (the baseline of every ratio).
pub fn balance_index() -> usize {
    index_of(Method::Mis(Heuristic::Balance), SphereSampling::Cone)
}

/// Seconds per sample per pixel of method `mi`: the fastest render of its two top rungs, per spp.
/// Taking the fastest of several seeds' renders (methods interleaved) keeps other processes on
/// the machine from inflating one method's cost more than another's.
pub fn cost_per_spp(records: &[Record], mi: usize, top: u32) -> f64 {
    records
        .iter()
        .filter(|r| r.method == mi && 2 * r.spp >= top)
        .map(|r| r.seconds / f64::from(r.spp))
        .fold(f64::INFINITY, f64::min)
}

/// The rungs (spp) of the ladder, in order.
pub fn rungs(records: &[Record]) -> Vec<u32> {
    let mut v: Vec<u32> = records.iter().map(|r| r.spp).collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// The top rung of the ladder (1 for none).
pub fn top_rung(records: &[Record]) -> u32 {
    rungs(records).last().copied().unwrap_or(1)
}

/// Mean, min and max of `f` over the seeds of method `mi` at `spp`.
pub fn over_seeds(records: &[Record], mi: usize, spp: u32, f: impl Fn(&Record) -> f64) -> (f64, f64, f64) {
    let vals: Vec<f64> = records.iter().filter(|r| r.method == mi && r.spp == spp).map(f).collect();
    let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (mean(vals.into_iter()), lo, hi)
}

/// The least-squares slope of ln(relative MSE) against ln(spp) of method `mi` over the rungs
/// (the error mean over seeds); NaN with fewer than two rungs of positive error.
pub fn convergence_slope(records: &[Record], mi: usize) -> f64 {
    let points: Vec<(f64, f64)> = rungs(records)
        .into_iter()
        .map(|spp| (f64::from(spp).ln(), over_seeds(records, mi, spp, |r| r.error.rel_mse).0))
        .filter(|(_, e)| *e > 0.0 && e.is_finite())
        .map(|(x, e)| (x, e.ln()))
        .collect();
    let n = points.len() as f64;
    let (mx, my) = (mean(points.iter().map(|p| p.0)), mean(points.iter().map(|p| p.1)));
    let sxy: f64 = points.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = points.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    if n >= 2.0 && sxx > 0.0 { sxy / sxx } else { f64::NAN }
}

/// Mean of the values (NaN for none).
pub fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for v in values {
        sum += v;
        n += 1;
    }
    sum / n as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_baseline_is_balance() {
        assert_eq!(methods()[balance_index()].label, "balance");
        assert_eq!(methods()[index_of(Method::LightOnly, SphereSampling::Area)].label, "light_area");
    }

    #[test]
    fn the_fixed_point_method_is_compared_with_f32_power() {
        let methods = methods();
        let fixed = methods.iter().position(|m| m.label == "power_fixed").unwrap();
        assert_eq!(f32_twin(fixed).map(|t| methods[t].label), Some("power"));
        assert!((0..methods.len()).filter(|&i| i != fixed).all(|i| f32_twin(i).is_none()));
    }
}

#[cfg(test)]
mod slope_tests {
    use super::*;
    use crate::study::metrics::ErrorStats;

    #[test]
    fn the_convergence_slope_is_that_of_the_fitted_power_law() {
        let record = |method, spp: u32, seed, rel_mse| Record {
            method,
            spp,
            seed,
            seconds: 1.0,
            error: ErrorStats { mse: rel_mse, rel_mse },
            mitsuba: None,
            vs_f32: None,
        };
        let mut records = Vec::new();
        for spp in [1u32, 2, 4, 8, 16] {
            // Method 0: 1 / spp^1.5 on average over two seeds; method 1: one rung only.
            let e = 0.3 * f64::from(spp).powf(-1.5);
            records.push(record(0, spp, 1, 0.5 * e));
            records.push(record(0, spp, 2, 1.5 * e));
        }
        records.push(record(1, 4, 1, 0.1));
        assert!((convergence_slope(&records, 0) + 1.5).abs() < 1e-9, "{}", convergence_slope(&records, 0));
        assert!(convergence_slope(&records, 1).is_nan());
    }
}
