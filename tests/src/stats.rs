//! Running statistics and the z-tests every unbiasedness check goes through: [`Stats`] (mean,
//! variance and the standard error of both, Welford in f64), [`check_unbiased`] against a closed
//! form and [`check_agreement`] of two estimates of a value that has no closed form.

use picomis::Rgb;
use statrs::distribution::{ContinuousCDF, StudentsT};

/// Running mean and variance of a stream of samples (Welford's algorithm, f64), with the third
/// and fourth central moments (Terriberry's and Pebay's updates) for the standard error of the
/// sample variance.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    n: u64,
    mean: f64,
    m2: f64,
    m3: f64,
    m4: f64,
}

impl Stats {
    /// An empty accumulator.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one sample.
    pub fn push(&mut self, x: f64) {
        let n1 = self.n as f64;
        self.n += 1;
        let n = self.n as f64;
        let d = x - self.mean;
        let dn = d / n;
        let term1 = d * dn * n1;
        self.m4 += term1 * dn * dn * (n * n - 3.0 * n + 3.0) + 6.0 * dn * dn * self.m2 - 4.0 * dn * self.m3;
        self.m3 += term1 * dn * (n - 2.0) - 3.0 * dn * self.m2;
        self.mean += d / self.n as f64;
        self.m2 += d * (x - self.mean);
    }

    /// Number of samples.
    pub fn n(&self) -> u64 {
        self.n
    }

    /// Sample mean.
    pub fn mean(&self) -> f64 {
        self.mean
    }

    /// Unbiased sample variance.
    pub fn variance(&self) -> f64 {
        if self.n > 1 { self.m2 / (self.n - 1) as f64 } else { f64::INFINITY }
    }

    /// Standard error of the mean.
    pub fn stderr(&self) -> f64 {
        (self.variance() / self.n as f64).sqrt()
    }

    /// Standard error of [`Stats::variance`], from the fourth central moment:
    /// Var[s^2] = (mu_4 - sigma^4 (n - 3) / (n - 1)) / n.
    pub fn variance_stderr(&self) -> f64 {
        if self.n < 4 {
            return f64::INFINITY;
        }
        let n = self.n as f64;
        let (mu4, var) = (self.m4 / n, self.variance());
        ((mu4 - var * var * (n - 3.0) / (n - 1.0)) / n).max(0.0).sqrt()
    }

    /// Adds all samples of `other` (Chan et al.'s pairwise update).
    pub fn merge(&mut self, other: &Stats) {
        let n = self.n + other.n;
        if n == 0 {
            return;
        }
        let d = other.mean - self.mean;
        let (na, nb, nf) = (self.n as f64, other.n as f64, n as f64);
        self.m4 += other.m4
            + d.powi(4) * na * nb * (na * na - na * nb + nb * nb) / nf.powi(3)
            + 6.0 * d * d * (na * na * other.m2 + nb * nb * self.m2) / (nf * nf)
            + 4.0 * d * (na * other.m3 - nb * self.m3) / nf;
        self.m3 += other.m3
            + d.powi(3) * na * nb * (na - nb) / (nf * nf)
            + 3.0 * d * (na * other.m2 - nb * self.m2) / nf;
        self.mean += d * nb / n as f64;
        self.m2 += other.m2 + d * d * na * nb / n as f64;
        self.n = n;
    }
}

/// Statistics of the three colour channels of a stream of RGB samples.
#[derive(Clone, Copy, Debug, Default)]
pub struct RgbStats(pub [Stats; 3]);

impl RgbStats {
    /// Adds one RGB sample.
    pub fn push(&mut self, c: Rgb) {
        for (s, v) in self.0.iter_mut().zip([c.x, c.y, c.z]) {
            s.push(f64::from(v));
        }
    }

    /// Adds the means of `other`'s three channels as one sample each (the mean of a replica).
    pub fn push_means(&mut self, other: &RgbStats) {
        for (s, o) in self.0.iter_mut().zip(&other.0) {
            s.push(o.mean());
        }
    }

    /// Adds all samples of `other`.
    pub fn merge(&mut self, other: &RgbStats) {
        for (s, o) in self.0.iter_mut().zip(&other.0) {
            s.merge(o);
        }
    }
}

/// Relative rounding allowance added to every z-test tolerance: the kernel computes in f32, so a
/// zero-variance estimator still carries a deterministic error of a few ulps.
pub const F32_ROUNDING: f64 = 1e-5;

/// Checks that `stats` is an unbiased estimate of `exact`: |mean - exact| < 4 stderr (plus a
/// relative f32 rounding allowance of [`F32_ROUNDING`]), and that the check is meaningful:
/// stderr <= `max_rel_stderr` * |exact|, so that a bias of a few percent would be detected.
/// `Err` holds the message of the failed check (suites that collect failures use this form).
pub fn check_unbiased(label: &str, stats: &Stats, exact: f64, max_rel_stderr: f64) -> Result<(), String> {
    check_z_within(label, stats.mean(), stats.stderr(), stats.n(), exact, 0.0, max_rel_stderr, 4.0)
}

/// Checks that two independent estimates of the same unknown value agree: |a - b| < 4 sigma with
/// sigma = sqrt(stderr_a^2 + stderr_b^2) (plus [`F32_ROUNDING`]), and that sigma <=
/// `max_rel_stderr` * |b| (`b` is the reference, usually the estimate with more samples).
pub fn check_agreement(label: &str, a: &Stats, b: &Stats, max_rel_stderr: f64) -> Result<(), String> {
    check_z_within(label, a.mean(), a.stderr(), a.n(), b.mean(), b.stderr(), max_rel_stderr, 4.0)
}

/// The z-test behind [`check_unbiased`] and [`check_agreement`]: `mean` (stderr `se`, `n`
/// samples) against `exact` (stderr `se_exact`, 0 for a closed form), |mean - exact| within
/// `z_max` standard errors (4 for one test; a family's: [`family_z`]).
#[allow(clippy::too_many_arguments)]
pub fn check_z_within(
    label: &str,
    mean: f64,
    se: f64,
    n: u64,
    exact: f64,
    se_exact: f64,
    max_rel_stderr: f64,
    z_max: f64,
) -> Result<(), String> {
    if !(exact.is_finite() && exact != 0.0 && se_exact.is_finite()) {
        return Err(format!("{label}: reference {exact} (stderr {se_exact}) is not a usable reference"));
    }
    if !(mean.is_finite() && se.is_finite()) {
        return Err(format!("{label}: mean {mean}, stderr {se} after {n} samples"));
    }
    let se = (se * se + se_exact * se_exact).sqrt();
    if se > max_rel_stderr * exact.abs() {
        return Err(format!(
            "{label}: stderr {se:.3e} is {:.2}% of the exact value {exact:.6e}: too noisy for a meaningful test",
            100.0 * se / exact.abs()
        ));
    }
    let tol = z_max * se + F32_ROUNDING * exact.abs();
    let z = if se > 0.0 { (mean - exact) / se } else { 0.0 };
    if (mean - exact).abs() > tol {
        return Err(format!(
            "{label}: mean {mean:.6e} vs exact {exact:.6e} (rel. error {:+.3e}), stderr {se:.3e}, z = {z:.2} \
             beyond {z_max:.2}, n = {n}",
            (mean - exact) / exact
        ));
    }
    Ok(())
}

/// Two-sided tail probability of |z| > 4 for a standard normal z: the level of every z-test here.
pub const Z_LEVEL: f64 = 6.334_248_366_623_996e-5;

/// The threshold on |mean - exact| / stderr of a z-test whose standard error has `dof` degrees of
/// freedom, at the two-sided level [`Z_LEVEL`] (|z| > 4 for a normal z): Student's t quantile,
/// which is 4 for many degrees of freedom and more for few (4.62 for 31, the standard error of 32
/// independent scrambles).
pub fn z_threshold(dof: f64) -> f64 {
    t_threshold(dof, Z_LEVEL)
}

/// [`z_threshold`] at the two-sided level `level`: Student's t quantile for `dof` degrees of
/// freedom, the normal one for many.
pub fn t_threshold(dof: f64, level: f64) -> f64 {
    if level == Z_LEVEL && (dof.is_nan() || dof >= 1e6) {
        return 4.0;
    }
    if dof.is_nan() || dof >= 1e6 {
        return family_z(1.0, level);
    }
    StudentsT::new(0.0, 1.0, dof.max(1.0)).map_or(f64::INFINITY, |t| t.inverse_cdf(1.0 - level / 2.0))
}

/// The threshold on |z| (normal) of each of `tests` z-tests such that the chance that any of
/// them fails by chance is at most `family_level` (Bonferroni: each at the two-sided level
/// family_level / tests). A suite of many checks at |z| < 4 each fails by chance on a fixed
/// share of its redraws; at this threshold on at most `family_level` of them.
pub fn family_z(tests: f64, family_level: f64) -> f64 {
    statrs::distribution::Normal::new(0.0, 1.0)
        .map_or(f64::INFINITY, |n| n.inverse_cdf(1.0 - family_level / tests.max(1.0) / 2.0))
}

/// An estimate of a mean with its standard error and that error's degrees of freedom: from
/// independent samples ([`MeanEstimate::of_samples`], the per-sample formula), or from the means
/// of independent replicas ([`MeanEstimate::of_replicas`]: the spread of the replicas' means,
/// valid however the samples within a replica are correlated, as those of one scrambled Sobol
/// sequence are).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeanEstimate {
    /// The mean of all samples.
    pub mean: f64,
    /// Its standard error.
    pub stderr: f64,
    /// The number of samples.
    pub n: u64,
    /// Degrees of freedom of the standard error.
    pub dof: f64,
}

impl MeanEstimate {
    /// The mean of independent samples, with the standard error sqrt(s^2 / n).
    pub fn of_samples(s: &Stats) -> Self {
        MeanEstimate { mean: s.mean(), stderr: s.stderr(), n: s.n(), dof: s.n().saturating_sub(1) as f64 }
    }

    /// The mean of `samples` samples taken as replicas of equal size whose means are `means`
    /// (independent randomisations): the standard error of the mean of the replicas' means, with
    /// one degree of freedom fewer than there are replicas.
    pub fn of_replicas(means: &Stats, samples: u64) -> Self {
        MeanEstimate {
            mean: means.mean(),
            stderr: means.stderr(),
            n: samples,
            dof: means.n().saturating_sub(1) as f64,
        }
    }

    /// The same estimate times `k` (an injected bias of k - 1; its standard error scales too).
    pub fn scaled(self, k: f64) -> Self {
        MeanEstimate { mean: k * self.mean, stderr: k * self.stderr, ..self }
    }

    /// (mean - exact) / stderr (0 for a zero standard error).
    pub fn z(&self, exact: f64) -> f64 {
        if self.stderr > 0.0 { (self.mean - exact) / self.stderr } else { 0.0 }
    }
}

/// The z-test of [`check_z_within`] for a [`MeanEstimate`] against a closed form: |mean - exact| within
/// [`z_threshold`] standard errors (for the estimate's degrees of freedom) plus [`F32_ROUNDING`],
/// with the standard error at most `max_rel_stderr` of the value. Returns the z-score.
pub fn check_mean(label: &str, est: &MeanEstimate, exact: f64, max_rel_stderr: f64) -> Result<f64, String> {
    let exact = MeanEstimate { mean: exact, stderr: 0.0, n: 0, dof: f64::INFINITY };
    check_means(label, est, &exact, max_rel_stderr)
}

/// [`check_mean`] against another estimate of the same value (`reference`, independent of
/// `est`): the standard errors combine, sqrt(se^2 + se_reference^2), with the fewer degrees of
/// freedom of the two (Student's t is then conservative), and the combined error must be at most
/// `max_rel_stderr` of the reference. Returns the z-score.
pub fn check_means(
    label: &str,
    est: &MeanEstimate,
    reference: &MeanEstimate,
    max_rel_stderr: f64,
) -> Result<f64, String> {
    check_means_at(label, est, reference, max_rel_stderr, Z_LEVEL)
}

/// [`check_mean`] at the two-sided level `level` (for a family of tests: [`family_z`]'s level).
pub fn check_mean_at(
    label: &str,
    est: &MeanEstimate,
    exact: f64,
    max_rel_stderr: f64,
    level: f64,
) -> Result<f64, String> {
    let exact = MeanEstimate { mean: exact, stderr: 0.0, n: 0, dof: f64::INFINITY };
    check_means_at(label, est, &exact, max_rel_stderr, level)
}

/// [`check_means`] at the two-sided level `level`.
pub fn check_means_at(
    label: &str,
    est: &MeanEstimate,
    reference: &MeanEstimate,
    max_rel_stderr: f64,
    level: f64,
) -> Result<f64, String> {
    let exact = reference.mean;
    let (mean, n) = (est.mean, est.n);
    let se = est.stderr.hypot(reference.stderr);
    let dof = if reference.stderr > 0.0 { est.dof.min(reference.dof) } else { est.dof };
    if !(exact.is_finite() && exact != 0.0 && reference.stderr.is_finite()) {
        return Err(format!(
            "{label}: reference {exact} (stderr {}) is not a usable reference",
            reference.stderr
        ));
    }
    if !(mean.is_finite() && se.is_finite()) {
        return Err(format!("{label}: mean {mean}, stderr {se} after {n} samples"));
    }
    if se > max_rel_stderr * exact.abs() {
        return Err(format!(
            "{label}: stderr {se:.3e} is {:.2}% of the exact value {exact:.6e}: too noisy for a meaningful test",
            100.0 * se / exact.abs()
        ));
    }
    let threshold = t_threshold(dof, level);
    let z = if se > 0.0 { (mean - exact) / se } else { 0.0 };
    if (mean - exact).abs() > threshold * se + F32_ROUNDING * exact.abs() {
        return Err(format!(
            "{label}: mean {mean:.6e} vs exact {exact:.6e} (rel. error {:+.3e}), stderr {se:.3e} ({dof} degrees \
             of freedom), z = {z:.2} beyond {threshold:.2}, n = {n}",
            (mean - exact) / exact
        ));
    }
    Ok(z)
}

/// Asserts [`check_unbiased`].
#[track_caller]
pub fn assert_unbiased(label: &str, stats: &Stats, exact: f64, max_rel_stderr: f64) {
    if let Err(e) = check_unbiased(label, stats, exact, max_rel_stderr) {
        panic!("{e}");
    }
}

/// [`assert_unbiased`] on each colour channel.
#[track_caller]
pub fn assert_unbiased_rgb(label: &str, stats: &RgbStats, exact: [f64; 3], max_rel_stderr: f64) {
    assert_unbiased_rgb_within(label, stats, exact, max_rel_stderr, 4.0);
}

/// [`assert_unbiased_rgb`] with the threshold `z_max` in place of 4 (a family's: [`family_z`]).
#[track_caller]
pub fn assert_unbiased_rgb_within(
    label: &str,
    stats: &RgbStats,
    exact: [f64; 3],
    max_rel_stderr: f64,
    z_max: f64,
) {
    for (c, (s, e)) in stats.0.iter().zip(exact).enumerate() {
        let label = format!("{label} [channel {c}]");
        if let Err(e) = check_z_within(&label, s.mean(), s.stderr(), s.n(), e, 0.0, max_rel_stderr, z_max) {
            panic!("{e}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_match_closed_forms() {
        let mut s = Stats::new();
        for x in [1.0, 2.0, 3.0, 4.0] {
            s.push(x);
        }
        assert_eq!(s.mean(), 2.5);
        assert!((s.variance() - 5.0 / 3.0).abs() < 1e-12);
        assert!((s.stderr() - (5.0 / 12.0f64).sqrt()).abs() < 1e-12);
    }

    #[test]
    #[should_panic(expected = "z =")]
    fn assert_unbiased_can_fail() {
        let mut s = Stats::new();
        for i in 0..1000 {
            s.push(1.0 + 0.01 * f64::from(i % 2));
        }
        assert_unbiased("biased", &s, 1.1, 0.02);
    }

    #[test]
    fn variance_stderr_matches_the_fourth_moment() {
        // The running moments against a two-pass computation of the same formula.
        let mut s = Stats::new();
        let xs: Vec<f64> = (0..4000).map(|i| f64::from(i % 4 == 0) * 3.0 + f64::from(i % 7) * 0.1).collect();
        for &x in &xs {
            s.push(x);
        }
        let n = xs.len() as f64;
        let mean = xs.iter().sum::<f64>() / n;
        let mu4 = xs.iter().map(|x| (x - mean).powi(4)).sum::<f64>() / n;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let expect = ((mu4 - var * var * (n - 3.0) / (n - 1.0)) / n).sqrt();
        assert!((s.variance_stderr() / expect - 1.0).abs() < 1e-9, "{} vs {expect}", s.variance_stderr());
        // Merging two halves gives the same moments as one pass.
        let (mut a, mut b) = (Stats::new(), Stats::new());
        for (i, &x) in xs.iter().enumerate() {
            if i < 1234 { a.push(x) } else { b.push(x) }
        }
        a.merge(&b);
        assert!((a.variance_stderr() / expect - 1.0).abs() < 1e-9);
        // A constant stream: no spread of the variance at all.
        let mut c = Stats::new();
        (0..100).for_each(|_| c.push(2.0));
        assert_eq!(c.variance_stderr(), 0.0);
    }

    #[test]
    fn family_z_is_bonferronis() {
        // One test at the level of |z| > 4 is 4; a thousand at a family level of 1e-3 each
        // stand at 1e-6 two-sided: 4.89.
        assert!((family_z(1.0, Z_LEVEL) - 4.0).abs() < 1e-6, "{}", family_z(1.0, Z_LEVEL));
        assert!((family_z(1000.0, 1e-3) - 4.891_638).abs() < 1e-4, "{}", family_z(1000.0, 1e-3));
        assert!(t_threshold(31.0, 1e-6) > family_z(1.0, 1e-6));
        assert!((t_threshold(f64::INFINITY, 1e-6) - family_z(1.0, 1e-6)).abs() < 1e-12);
    }

    #[test]
    fn z_threshold_is_students_t_at_the_level_of_four_sigma() {
        assert_eq!(z_threshold(f64::INFINITY), 4.0);
        assert!((z_threshold(1e5) - 4.0).abs() < 1e-3, "{}", z_threshold(1e5));
        // Student's t with 31 degrees of freedom: P(|T| > 4.62) = 6.3e-5.
        let t31 = z_threshold(31.0);
        assert!((4.55..4.7).contains(&t31), "{t31}");
        assert!(z_threshold(7.0) > t31);
    }

    #[test]
    fn check_mean_catches_an_injected_bias_that_check_z_of_the_same_data_would_pass() {
        // 32 replica means spread by 1e-3 around 1 (the error of the mean: 1.8e-4), while the
        // samples themselves spread by 0.1 (an independent-sample standard error of 1e-2 / 16).
        let mut means = Stats::new();
        for j in 0..32 {
            means.push(1.0 + 1e-3 * (f64::from(j % 4) - 1.5));
        }
        let est = MeanEstimate::of_replicas(&means, 32 * 6250);
        assert!(check_mean("unbiased", &est, 1.0, 0.02).is_ok());
        let biased = est.scaled(1.01);
        assert!(check_mean("biased", &biased, 1.0, 0.02).unwrap_err().contains("beyond"));
    }

    #[test]
    fn merged_stats_equal_one_pass() {
        let xs: Vec<f64> = (0..50).map(|i| f64::from(i * i % 17) - 3.5).collect();
        let (mut all, mut a, mut b) = (Stats::new(), Stats::new(), Stats::new());
        for (i, &x) in xs.iter().enumerate() {
            all.push(x);
            if i < 20 { a.push(x) } else { b.push(x) }
        }
        a.merge(&b);
        assert_eq!(a.n(), all.n());
        assert!((a.mean() - all.mean()).abs() < 1e-12 && (a.variance() - all.variance()).abs() < 1e-12);
        a.merge(&Stats::new());
        assert!((a.variance() - all.variance()).abs() < 1e-12);
    }

    #[test]
    fn agreement_uses_both_standard_errors() {
        let (mut a, mut b) = (Stats::new(), Stats::new());
        for i in 0..1000 {
            a.push(1.0 + 0.1 * f64::from(i % 2));
            b.push(1.06 + 0.1 * f64::from(i % 2));
        }
        // Means 1.05 and 1.11, each with stderr ~1.6e-3: 0.06 apart is ~27 combined sigmas.
        assert!(check_agreement("apart", &a, &b, 0.02).unwrap_err().contains("z ="));
        assert!(check_agreement("same", &a, &a, 0.02).is_ok());
        // Too noisy to be meaningful.
        assert!(check_agreement("noisy", &a, &b, 1e-4).unwrap_err().contains("too noisy"));
    }

    #[test]
    #[should_panic(expected = "too noisy")]
    fn assert_unbiased_rejects_vacuous_checks() {
        let mut s = Stats::new();
        for i in 0..10 {
            s.push(f64::from(i));
        }
        assert_unbiased("noisy", &s, 4.5, 0.02);
    }
}
