//! Shared helpers of the statistical test suites of picomis (the suites are in `tests/tests/*.rs`):
//!
//! - [`Stats`]: running mean and standard error (Welford, f64), and [`assert_unbiased`] /
//!   [`check_unbiased`], the z-test every unbiasedness check goes through (|mean - exact| <
//!   4 stderr, and the stderr must be small enough for the check to be able to fail), with
//!   [`check_agreement`] for two estimates of a value that has no closed form;
//! - [`chi2_pooled`] / [`assert_chi2`]: Pearson's chi-square with Mitsuba's pooling of cells with
//!   fewer than 5 expected samples and a Sidak-corrected significance level;
//! - [`Histogram2d`]: a chart of the sample space on [0, 1)^2 binned into cells, whose expected
//!   counts come from integrating a density numerically (adaptive Gauss-Legendre per cell);
//! - [`Cap`]: a polar chart of (part of) the sphere of directions around an axis;
//! - closed forms: [`sphere_irradiance`], [`sphere_irradiance_at`], [`lambert_polygon_irradiance`],
//!   [`polygon_solid_angle`], [`cone_measure`];
//! - scene builders: [`camera`], [`quad_corners`], [`shading_hit`], [`direct_stats`].
//!
//! Tests are host code: everything here computes in f64 unless it calls the kernel.

use picomis::{
    CameraDesc, FovAxis, Hit, Ray, RenderSettings, Rgb, Sampler, Scene, ShapeId, SurfacePoint,
    TechniqueEstimate, Vec2, Vec3, estimate_direct, trace,
};
use statrs::distribution::{ChiSquared, ContinuousCDF};
use std::f64::consts::PI;
use std::ops::{Add, Mul, Neg, Sub};

/// Every heuristic of the kernel's list ([`picomis::Method::ALL`], default parameters) and the
/// power heuristic with beta 0.5, for tests that sweep them all.
pub fn heuristics() -> Vec<picomis::Heuristic> {
    let mut all: Vec<picomis::Heuristic> = picomis::Method::ALL
        .iter()
        .filter_map(|m| match m {
            picomis::Method::Mis(h) => Some(*h),
            _ => None,
        })
        .collect();
    all.push(picomis::Heuristic::Power { beta: 0.5 });
    all
}

// ---------------------------------------------------------------------------------------------
// f64 vectors (the kernel's glam is built without f64 types, and stays so)

/// A 3-vector in f64.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DVec3 {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
}

impl DVec3 {
    /// (1, 0, 0).
    pub const X: Self = Self::new(1.0, 0.0, 0.0);
    /// (0, 1, 0).
    pub const Y: Self = Self::new(0.0, 1.0, 0.0);
    /// (0, 0, 1).
    pub const Z: Self = Self::new(0.0, 0.0, 1.0);
    /// (0, 0, 0).
    pub const ZERO: Self = Self::new(0.0, 0.0, 0.0);

    /// A vector.
    pub const fn new(x: f64, y: f64, z: f64) -> Self {
        Self { x, y, z }
    }
    /// Dot product.
    pub fn dot(self, o: Self) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    /// Cross product.
    pub fn cross(self, o: Self) -> Self {
        Self::new(self.y * o.z - self.z * o.y, self.z * o.x - self.x * o.z, self.x * o.y - self.y * o.x)
    }
    /// Squared length.
    pub fn length_squared(self) -> f64 {
        self.dot(self)
    }
    /// Length.
    pub fn length(self) -> f64 {
        self.length_squared().sqrt()
    }
    /// Unit vector.
    pub fn normalize(self) -> Self {
        self * (1.0 / self.length())
    }
}

impl Add for DVec3 {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl Sub for DVec3 {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl Mul<f64> for DVec3 {
    type Output = Self;
    fn mul(self, s: f64) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}

impl Neg for DVec3 {
    type Output = Self;
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

// ---------------------------------------------------------------------------------------------
// Running statistics

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
    check_z(label, stats.mean(), stats.stderr(), stats.n(), exact, 0.0, max_rel_stderr)
}

/// Checks that two independent estimates of the same unknown value agree: |a - b| < 4 sigma with
/// sigma = sqrt(stderr_a^2 + stderr_b^2) (plus [`F32_ROUNDING`]), and that sigma <=
/// `max_rel_stderr` * |b| (`b` is the reference, usually the estimate with more samples).
pub fn check_agreement(label: &str, a: &Stats, b: &Stats, max_rel_stderr: f64) -> Result<(), String> {
    check_z(label, a.mean(), a.stderr(), a.n(), b.mean(), b.stderr(), max_rel_stderr)
}

/// The z-test behind [`check_unbiased`] and [`check_agreement`]: `mean` (stderr `se`, `n`
/// samples) against `exact` (stderr `se_exact`, 0 for a closed form).
pub fn check_z(
    label: &str,
    mean: f64,
    se: f64,
    n: u64,
    exact: f64,
    se_exact: f64,
    max_rel_stderr: f64,
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
    let tol = 4.0 * se + F32_ROUNDING * exact.abs();
    let z = if se > 0.0 { (mean - exact) / se } else { 0.0 };
    if (mean - exact).abs() > tol {
        return Err(format!(
            "{label}: mean {mean:.6e} vs exact {exact:.6e} (rel. error {:+.3e}), stderr {se:.3e}, z = {z:.2}, n = {n}",
            (mean - exact) / exact
        ));
    }
    Ok(())
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
    for (c, (s, e)) in stats.0.iter().zip(exact).enumerate() {
        assert_unbiased(&format!("{label} [channel {c}]"), s, e, max_rel_stderr);
    }
}

// ---------------------------------------------------------------------------------------------
// Chi-square

/// Outcome of a pooled chi-square test.
#[derive(Clone, Copy, Debug)]
pub struct Chi2 {
    /// Pearson statistic.
    pub statistic: f64,
    /// Degrees of freedom (cells after pooling minus one).
    pub dof: usize,
    /// P-value: probability of a statistic at least this large under the null hypothesis.
    pub p_value: f64,
}

/// Per-test significance level that keeps the family-wise level at `alpha` over `tests`
/// independent tests (Sidak correction).
pub fn sidak(alpha: f64, tests: usize) -> f64 {
    1.0 - (1.0 - alpha).powf(1.0 / tests.max(1) as f64)
}

/// Pearson's chi-square of observed against expected counts, pooled as in Mitsuba's `chi2`
/// test: cells are visited by increasing expected count; cells with fewer than 5 expected
/// samples go into a pool, which keeps absorbing cells until it holds at least 5. Cells with
/// expected count 0 must stay (nearly) empty: more than `1e-5 * total` samples in them is an
/// error (samples outside the support of the pdf).
pub fn chi2_pooled(observed: &[f64], expected: &[f64]) -> Result<Chi2, String> {
    assert_eq!(observed.len(), expected.len());
    let total: f64 = observed.iter().sum();
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let (mut stat, mut cells) = (0.0, 0usize);
    let (mut pool_obs, mut pool_exp) = (0.0, 0.0);
    let mut in_empty = 0.0;
    for i in order {
        let (o, e) = (observed[i], expected[i]);
        if e.is_nan() || e <= 0.0 {
            in_empty += o;
            continue;
        }
        if e < 5.0 || (pool_exp > 0.0 && pool_exp < 5.0) {
            pool_obs += o;
            pool_exp += e;
        } else {
            stat += (o - e) * (o - e) / e;
            cells += 1;
        }
    }
    if in_empty > 1e-5 * total {
        return Err(format!("{in_empty} samples fell where the pdf integrates to zero"));
    }
    if pool_exp > 0.0 {
        stat += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
        cells += 1;
    }
    if cells < 2 {
        return Err(format!("only {cells} cell(s) after pooling: the test cannot fail"));
    }
    let dof = cells - 1;
    let dist = ChiSquared::new(dof as f64).map_err(|e| e.to_string())?;
    Ok(Chi2 { statistic: stat, dof, p_value: dist.sf(stat) })
}

/// Asserts that the chi-square test of `observed` against `expected` passes at level 0.01,
/// Sidak-corrected for `tests` tests in the suite.
#[track_caller]
pub fn assert_chi2(label: &str, observed: &[f64], expected: &[f64], tests: usize) -> Chi2 {
    let level = sidak(0.01, tests);
    match chi2_pooled(observed, expected) {
        Ok(c) => {
            println!("{label}: chi-square {:.1}, {} dof, p = {:.3}", c.statistic, c.dof, c.p_value);
            assert!(
                c.p_value >= level,
                "{label}: chi-square {:.1} with {} dof, p = {:.3e} < {level:.3e}: samples do not follow the pdf; \
                 worst cells (index, observed, expected): {:?}",
                c.statistic,
                c.dof,
                c.p_value,
                worst_cells(observed, expected, 6)
            );
            c
        }
        Err(e) => panic!("{label}: {e}"),
    }
}

/// The `k` cells with the largest chi-square terms (cells expecting >= 5 samples), for messages.
pub fn worst_cells(observed: &[f64], expected: &[f64], k: usize) -> Vec<(usize, f64, f64)> {
    let mut v: Vec<(usize, f64, f64)> = (0..observed.len())
        .filter(|&i| expected[i] >= 5.0)
        .map(|i| (i, observed[i], (expected[i] * 10.0).round() / 10.0))
        .collect();
    let term = |&(_, o, e): &(usize, f64, f64)| (o - e) * (o - e) / e;
    v.sort_by(|a, b| term(b).total_cmp(&term(a)));
    v.truncate(k);
    v
}

// ---------------------------------------------------------------------------------------------
// Numerical integration and histograms

/// Gauss-Legendre nodes on [0, 1] (5 points) and their weights (summing to 1).
const GL_NODES: [f64; 5] =
    [0.046_910_077_030_668, 0.230_765_344_947_158_45, 0.5, 0.769_234_655_052_841_5, 0.953_089_922_969_332];
const GL_WEIGHTS: [f64; 5] = [
    0.118_463_442_528_094_54,
    0.239_314_335_249_683_23,
    0.284_444_444_444_444_44,
    0.239_314_335_249_683_23,
    0.118_463_442_528_094_54,
];

/// Integral of `f` over [a0, a1] x [b0, b1]: `sub` x `sub` sub-cells, 5 x 5 Gauss-Legendre nodes
/// each. No node lies on an edge, so a density that jumps on a cell edge is integrated exactly
/// as if it were smooth.
pub fn integrate_cell(f: &impl Fn(f64, f64) -> f64, a: [f64; 2], b: [f64; 2], sub: usize) -> f64 {
    let (da, db) = ((a[1] - a[0]) / sub as f64, (b[1] - b[0]) / sub as f64);
    let mut sum = 0.0;
    for i in 0..sub {
        for j in 0..sub {
            for (&xa, &wa) in GL_NODES.iter().zip(&GL_WEIGHTS) {
                for (&xb, &wb) in GL_NODES.iter().zip(&GL_WEIGHTS) {
                    let u = a[0] + (i as f64 + xa) * da;
                    let v = b[0] + (j as f64 + xb) * db;
                    sum += wa * wb * f(u, v);
                }
            }
        }
    }
    sum * da * db
}

/// Adaptive version of [`integrate_cell`]: compares the cell's 5 x 5 Gauss-Legendre rule with
/// the same rule on its four quarters and recurses into the quarters (at most `depth` times)
/// until the two agree to `tol` (absolute) or a relative 1e-7. Sharp lobes (GGX at small alpha
/// and grazing angles) need it: a fixed rule overestimates their mass by percents.
pub fn integrate_adaptive(
    f: &impl Fn(f64, f64) -> f64,
    a: [f64; 2],
    b: [f64; 2],
    tol: f64,
    depth: u32,
) -> f64 {
    let coarse = integrate_cell(f, a, b, 1);
    adaptive_step(f, a, b, tol, depth, coarse)
}

fn adaptive_step(
    f: &impl Fn(f64, f64) -> f64,
    a: [f64; 2],
    b: [f64; 2],
    tol: f64,
    depth: u32,
    coarse: f64,
) -> f64 {
    let (am, bm) = (0.5 * (a[0] + a[1]), 0.5 * (b[0] + b[1]));
    let quarters = [
        ([a[0], am], [b[0], bm]),
        ([am, a[1]], [b[0], bm]),
        ([a[0], am], [bm, b[1]]),
        ([am, a[1]], [bm, b[1]]),
    ];
    let parts = quarters.map(|(qa, qb)| integrate_cell(f, qa, qb, 1));
    let fine: f64 = parts.iter().sum();
    if depth == 0 || (fine - coarse).abs() <= tol.max(1e-7 * fine.abs()) {
        return fine;
    }
    quarters.iter().zip(parts).map(|(&(qa, qb), p)| adaptive_step(f, qa, qb, 0.25 * tol, depth - 1, p)).sum()
}

/// A histogram of samples charted on [0, 1)^2 (`na` x `nb` cells), plus a cell for samples that
/// fall outside the chart and one for "no sample" (a sampler returning `None`).
#[derive(Clone, Debug)]
pub struct Histogram2d {
    na: usize,
    nb: usize,
    /// Counts: `na * nb` cells, then outside, then no sample.
    pub observed: Vec<f64>,
    /// Samples drawn.
    pub samples: u64,
}

impl Histogram2d {
    /// An empty histogram of `na` x `nb` cells.
    pub fn new(na: usize, nb: usize) -> Self {
        Self { na, nb, observed: vec![0.0; na * nb + 2], samples: 0 }
    }

    /// Records one sample at chart coordinates `ab` (`None`: outside the chart).
    pub fn add(&mut self, ab: Option<(f64, f64)>) {
        self.samples += 1;
        let cells = self.na * self.nb;
        let slot = match ab {
            Some((a, b)) if (0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b) => {
                let i = ((a * self.na as f64) as usize).min(self.na - 1);
                let j = ((b * self.nb as f64) as usize).min(self.nb - 1);
                i * self.nb + j
            }
            _ => cells,
        };
        self.observed[slot] += 1.0;
    }

    /// Records a sampler returning nothing.
    pub fn add_none(&mut self) {
        self.samples += 1;
        let n = self.observed.len();
        self.observed[n - 1] += 1.0;
    }

    /// Number of chart cells (`na * nb`); `observed[cells]` counts samples outside the chart and
    /// `observed[cells + 1]` samplers that returned nothing.
    pub fn cells(&self) -> usize {
        self.na * self.nb
    }

    /// Expected counts of the chart cells for `n` samples of density `density(a, b)` in chart
    /// coordinates (the pdf times the chart's Jacobian), laid out like `observed` with 0 for the
    /// outside and "no sample" cells; also the integral of the density over the chart.
    pub fn cell_expectations(&self, n: f64, density: impl Fn(f64, f64) -> f64) -> (Vec<f64>, f64) {
        let mut e = vec![0.0; self.observed.len()];
        let mut total = 0.0;
        for i in 0..self.na {
            for j in 0..self.nb {
                let a = [i as f64 / self.na as f64, (i + 1) as f64 / self.na as f64];
                let b = [j as f64 / self.nb as f64, (j + 1) as f64 / self.nb as f64];
                // Absolute error per cell well below a hundredth of a sample.
                let p = integrate_adaptive(&density, a, b, 1e-2 / n, 5);
                total += p;
                e[i * self.nb + j] = n * p;
            }
        }
        (e, total)
    }

    /// Expected counts for the samples recorded: the chart is assumed to hold the whole support
    /// (outside: 0 expected), and the "no sample" cell gets the rest of the probability.
    /// Also returns the integral of the density over the chart.
    pub fn expected(&self, density: impl Fn(f64, f64) -> f64) -> (Vec<f64>, f64) {
        let n = self.samples as f64;
        let (mut e, total) = self.cell_expectations(n, density);
        let last = e.len() - 1;
        e[last] = (n * (1.0 - total)).max(0.0);
        (e, total)
    }

    /// Chi-square test of the recorded samples against `density` (see [`Histogram2d::expected`]).
    #[track_caller]
    pub fn assert_matches(&self, label: &str, density: impl Fn(f64, f64) -> f64, tests: usize) -> Chi2 {
        let (e, total) = self.expected(density);
        assert!(
            total < 1.0 + 1e-3,
            "{label}: the pdf integrates to {total} > 1 over the chart (a pdf that is too large)"
        );
        assert_chi2(label, &self.observed, &e, tests)
    }
}

/// Draws `n` samples with `sample(u)` (random numbers from one deterministic [`Sampler`] stream)
/// and histograms them with `chart` (`None` from `sample`: no sample).
pub fn histogram<S>(
    na: usize,
    nb: usize,
    n: usize,
    seed: u32,
    mut sample: impl FnMut(Vec2) -> Option<S>,
    chart: impl Fn(&S) -> Option<(f64, f64)>,
) -> Histogram2d {
    let mut h = Histogram2d::new(na, nb);
    let mut rng = Sampler::new(seed, 0xC415, 0);
    for _ in 0..n {
        match sample(rng.next_2d()) {
            Some(s) => h.add(chart(&s)),
            None => h.add_none(),
        }
    }
    h
}

// ---------------------------------------------------------------------------------------------
// Direction charts

/// f32 vector to f64.
pub fn d3(v: Vec3) -> DVec3 {
    DVec3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z))
}

/// f64 vector to f32.
pub fn f3(v: DVec3) -> Vec3 {
    Vec3::new(v.x as f32, v.y as f32, v.z as f32)
}

/// An orthonormal frame around unit `n` (f64).
pub fn frame(n: DVec3) -> [DVec3; 3] {
    let n = n.normalize();
    let helper = if n.x.abs() < 0.6 { DVec3::X } else { DVec3::Y };
    let t = helper.cross(n).normalize();
    [t, n.cross(t), n]
}

/// A polar chart of the directions within `theta_max` of an axis: a = theta / theta_max,
/// b = phi / (2 pi). `theta_max = pi` charts the whole sphere, `pi / 2` a hemisphere.
#[derive(Clone, Copy, Debug)]
pub struct Cap {
    /// Tangent, bitangent, axis.
    pub frame: [DVec3; 3],
    /// Largest polar angle charted.
    pub theta_max: f64,
}

impl Cap {
    /// The cap of half-angle `theta_max` around `axis`.
    pub fn new(axis: DVec3, theta_max: f64) -> Self {
        Self { frame: frame(axis), theta_max }
    }

    /// Chart coordinates of direction `v` (any length), `None` beyond `theta_max`.
    /// The polar angle comes from atan2 of the tangential and axial parts, so it stays accurate
    /// for directions a micro-radian off the axis.
    pub fn coords(&self, v: DVec3) -> Option<(f64, f64)> {
        let [t, b, n] = self.frame;
        let (x, y, z) = (v.dot(t), v.dot(b), v.dot(n));
        let theta = (x * x + y * y).sqrt().atan2(z);
        let a = theta / self.theta_max;
        let phi = y.atan2(x).rem_euclid(2.0 * PI);
        (a <= 1.0).then_some((a, phi / (2.0 * PI)))
    }

    /// The unit direction at chart coordinates (a, b).
    pub fn direction(&self, a: f64, b: f64) -> DVec3 {
        let [t, bt, n] = self.frame;
        let (theta, phi) = (a * self.theta_max, b * 2.0 * PI);
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        t * (st * cp) + bt * (st * sp) + n * ct
    }

    /// Solid angle per unit chart area at (a, b): sin(theta) theta_max 2 pi.
    pub fn jacobian(&self, a: f64) -> f64 {
        (a * self.theta_max).sin() * self.theta_max * 2.0 * PI
    }

    /// Density in chart coordinates of a solid-angle `pdf` of directions.
    pub fn density<'a>(&'a self, pdf: impl Fn(DVec3) -> f64 + 'a) -> impl Fn(f64, f64) -> f64 + 'a {
        move |a, b| pdf(self.direction(a, b)) * self.jacobian(a)
    }
}

// ---------------------------------------------------------------------------------------------
// Closed forms

/// Solid angle 2 pi (1 - cos theta_max) of the cone a sphere of radius r subtends at distance d,
/// computed as 2 pi s^2 / (1 + sqrt(1 - s^2)) with s = r/d (accurate for tiny r/d).
pub fn cone_measure(r_over_d: f64) -> f64 {
    let s2 = r_over_d * r_over_d;
    2.0 * PI * s2 / (1.0 + (1.0 - s2).sqrt())
}

/// Irradiance from a sphere of radiance `radiance` and radius `r`, centre at distance `d`,
/// whose centre is `theta` off the receiver's normal and fully above its horizon:
/// E = pi L (r/d)^2 cos(theta).
pub fn sphere_irradiance(radiance: f64, r: f64, d: f64, cos_theta: f64) -> f64 {
    assert!(cos_theta >= r / d - 1e-12, "sphere not fully above the horizon");
    PI * radiance * (r / d) * (r / d) * cos_theta
}

/// Irradiance at `x` (unit normal `n`) from a sphere light of radiance `radiance`, centre `c`
/// and radius `r`, fully above the horizon of `x` ([`sphere_irradiance`] in any position).
pub fn sphere_irradiance_at(x: DVec3, n: DVec3, c: DVec3, r: f64, radiance: f64) -> f64 {
    let v = c - x;
    let d = v.length();
    sphere_irradiance(radiance, r, d, n.dot(v) / d)
}

/// Irradiance at `x` (unit normal `n`) from a convex polygon of constant `radiance` entirely
/// above the horizon, by Lambert's formula E = (L/2) |sum_k acos(v_k . v_k+1) n . normalize(v_k x
/// v_k+1)| with v_k the unit vectors to the vertices (either winding).
pub fn lambert_polygon_irradiance(x: DVec3, n: DVec3, verts: &[DVec3], radiance: f64) -> f64 {
    let k = verts.len();
    let mut sum = 0.0f64;
    for i in 0..k {
        let a = (verts[i] - x).normalize();
        let b = (verts[(i + 1) % k] - x).normalize();
        let angle = a.dot(b).clamp(-1.0, 1.0).acos();
        sum += angle * n.dot(a.cross(b).normalize());
    }
    0.5 * radiance * sum.abs()
}

/// Solid angle of a convex planar polygon seen from `x`: a fan of triangles, each by Van
/// Oosterom and Strackee's formula tan(Omega/2) = |a.(b x c)| / (abc + (a.b)c + (a.c)b + (b.c)a).
pub fn polygon_solid_angle(x: DVec3, verts: &[DVec3]) -> f64 {
    let tri = |a: DVec3, b: DVec3, c: DVec3| {
        let (la, lb, lc) = (a.length(), b.length(), c.length());
        let num = a.dot(b.cross(c)).abs();
        let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
        2.0 * num.atan2(den)
    };
    (1..verts.len() - 1).map(|i| tri(verts[0] - x, verts[i] - x, verts[i + 1] - x)).sum()
}

/// Rec. 709 luminance in f64 (the kernel's power-based light selection uses it).
pub fn luminance(c: Rgb) -> f64 {
    0.2126 * f64::from(c.x) + 0.7152 * f64::from(c.y) + 0.0722 * f64::from(c.z)
}

/// The three channels of a colour in f64.
pub fn rgb64(c: Rgb) -> [f64; 3] {
    [f64::from(c.x), f64::from(c.y), f64::from(c.z)]
}

// ---------------------------------------------------------------------------------------------
// Scene builders

/// A camera looking down at the origin from +y (tests mostly shade hand-built points).
pub fn camera() -> CameraDesc {
    CameraDesc {
        origin: Vec3::new(0.0, 6.0, 6.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_deg: 30.0,
        fov_axis: FovAxis::Y,
        near_clip: 0.0,
    }
}

/// The corners of the parallelogram `p0, p0 + e1, p0 + e1 + e2, p0 + e2` (front side along
/// e1 x e2).
pub fn quad_corners(p0: Vec3, e1: Vec3, e2: Vec3) -> [Vec3; 4] {
    [p0, p0 + e1, p0 + e1 + e2, p0 + e2]
}

/// A square floor of half-size `half` in the plane y = 0, facing +y.
pub fn floor_corners(half: f32) -> [Vec3; 4] {
    quad_corners(
        Vec3::new(-half, 0.0, half),
        Vec3::new(2.0 * half, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -2.0 * half),
    )
}

/// The hit record of a shading point `p` with front normal `n` on object `object`.
pub fn shading_hit(object: ShapeId, p: Vec3, n: Vec3) -> Hit {
    Hit { t: 1.0, object, point: SurfacePoint { p, n }, front: true }
}

/// `n` direct-lighting estimates at `hit` towards `wo` (estimate i draws from the settings'
/// sample stream for (seed, pixel `stream`, sample i): independent for the independent stream,
/// one scrambled Sobol sequence for sobol, whose mean then varies less than independent ones'), as running statistics of the total radiance and of the
/// light- and BSDF-technique parts, with the number of estimates whose output (contributions or
/// weight sums) was not finite and how many samples of each technique found light.
pub fn direct_stats<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    hit: &Hit,
    wo: Vec3,
    stream: u32,
    n: u32,
) -> DirectStats {
    let mut out = DirectStats::default();
    for i in 0..n {
        let mut sampler = Sampler::with_kind(settings.sampler(), settings.seed(), stream, i);
        let (light, bsdf) = estimate_direct(scene, settings, hit, wo, &mut sampler);
        let finite = |t: &TechniqueEstimate| {
            t.contribution.is_finite() && t.weight_sum.is_finite() && t.weight_sum >= 0.0
        };
        if !(finite(&light) && finite(&bsdf)) {
            out.non_finite += 1;
        }
        out.light_found += u64::from(light.found);
        out.bsdf_found += u64::from(bsdf.found);
        out.total.push(light.contribution + bsdf.contribution);
        out.light.push(light.contribution);
        out.bsdf.push(bsdf.contribution);
    }
    out
}

/// `n` independent estimates of the radiance along `ray` through [`picomis::trace`].
pub fn trace_stats<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    ray: &Ray,
    stream: u32,
    n: u32,
) -> RgbStats {
    let mut out = RgbStats::default();
    for i in 0..n {
        let mut sampler = Sampler::with_kind(settings.sampler(), settings.seed(), stream, i);
        out.push(trace(scene, settings, ray, 0.0, &mut sampler).radiance());
    }
    out
}

/// Statistics of direct-lighting estimates: total and per technique.
#[derive(Clone, Copy, Debug, Default)]
pub struct DirectStats {
    /// Light + BSDF contributions.
    pub total: RgbStats,
    /// Light-sampling contribution.
    pub light: RgbStats,
    /// BSDF-sampling contribution.
    pub bsdf: RgbStats,
    /// Estimates with a non-finite contribution or weight sum (or a negative weight sum).
    pub non_finite: u64,
    /// Light samples that found light.
    pub light_found: u64,
    /// BSDF samples that found light.
    pub bsdf_found: u64,
}

impl DirectStats {
    /// Adds the estimates of `other` (for instance those taken at another shading point).
    pub fn merge(&mut self, other: &DirectStats) {
        self.total.merge(&other.total);
        self.light.merge(&other.light);
        self.bsdf.merge(&other.bsdf);
        self.non_finite += other.non_finite;
        self.light_found += other.light_found;
        self.bsdf_found += other.bsdf_found;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Irradiance from a parallelogram by brute-force quadrature over its area, in f64:
    /// E = L integral cos_x cos_y / r^2 dA.
    fn quad_irradiance_by_quadrature(x: DVec3, n: DVec3, p0: DVec3, e1: DVec3, e2: DVec3, l: f64) -> f64 {
        let ny = e1.cross(e2).normalize();
        let area = e1.cross(e2).length();
        let f = |s: f64, t: f64| {
            let y = p0 + e1 * s + e2 * t;
            let v = y - x;
            let d2 = v.length_squared();
            let d = d2.sqrt();
            l * n.dot(v).max(0.0) / d * ny.dot(-v).abs() / d / d2
        };
        let mut sum = 0.0;
        let k = 16;
        for i in 0..k {
            for j in 0..k {
                let a = [i as f64 / k as f64, (i + 1) as f64 / k as f64];
                let b = [j as f64 / k as f64, (j + 1) as f64 / k as f64];
                sum += integrate_cell(&f, a, b, 2);
            }
        }
        sum * area
    }

    #[test]
    fn lambert_formula_matches_quadrature() {
        let x = DVec3::new(0.1, 0.0, -0.2);
        let n = DVec3::Y;
        for (p0, e1, e2) in [
            (DVec3::new(-0.5, 1.0, -0.5), DVec3::X, DVec3::Z),
            (DVec3::new(0.3, 2.0, 0.1), DVec3::new(1.5, 0.4, 0.0), DVec3::new(0.0, 0.3, -1.0)),
            (DVec3::new(-3.0, 0.5, -3.0), DVec3::new(6.0, 0.0, 0.0), DVec3::new(0.0, 0.0, 6.0)),
        ] {
            let verts = [p0, p0 + e1, p0 + e1 + e2, p0 + e2];
            let lambert = lambert_polygon_irradiance(x, n, &verts, 2.0);
            let mut rev = verts;
            rev.reverse();
            assert!((lambert_polygon_irradiance(x, n, &rev, 2.0) - lambert).abs() < 1e-12);
            let quad = quad_irradiance_by_quadrature(x, n, p0, e1, e2, 2.0);
            assert!((lambert / quad - 1.0).abs() < 1e-6, "{lambert} vs {quad}");
        }
        // A huge square close above: E -> pi L.
        let big = [
            DVec3::new(-1e4, 1.0, -1e4),
            DVec3::new(1e4, 1.0, -1e4),
            DVec3::new(1e4, 1.0, 1e4),
            DVec3::new(-1e4, 1.0, 1e4),
        ];
        assert!((lambert_polygon_irradiance(DVec3::ZERO, n, &big, 1.0) / PI - 1.0).abs() < 1e-3);
    }

    #[test]
    fn solid_angle_formula_matches_quadrature() {
        let x = DVec3::new(0.2, -0.1, 0.0);
        let (p0, e1, e2) =
            (DVec3::new(-0.4, 1.0, -0.3), DVec3::new(1.2, 0.2, 0.0), DVec3::new(0.1, 0.0, 0.9));
        let ny = e1.cross(e2).normalize();
        let area = e1.cross(e2).length();
        let f = |s: f64, t: f64| {
            let v = p0 + e1 * s + e2 * t - x;
            ny.dot(v).abs() / v.length().powi(3)
        };
        let quad = integrate_cell(&f, [0.0, 1.0], [0.0, 1.0], 32) * area;
        let formula = polygon_solid_angle(x, &[p0, p0 + e1, p0 + e1 + e2, p0 + e2]);
        assert!((formula / quad - 1.0).abs() < 1e-9, "{formula} vs {quad}");
        // A whole hemisphere: a huge square just above.
        let big = [
            DVec3::new(-1e5, 1e-3, -1e5),
            DVec3::new(1e5, 1e-3, -1e5),
            DVec3::new(1e5, 1e-3, 1e5),
            DVec3::new(-1e5, 1e-3, 1e5),
        ];
        assert!((polygon_solid_angle(DVec3::ZERO, &big) / (2.0 * PI) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn cone_measure_is_accurate() {
        let r = 0.5f64;
        let naive = 2.0 * PI * (1.0 - (1.0 - r * r).sqrt());
        assert!((cone_measure(r) / naive - 1.0).abs() < 1e-14);
        assert!((cone_measure(1e-6) / (PI * 1e-12) - 1.0).abs() < 1e-11);
    }

    #[test]
    fn cap_chart_round_trips_and_integrates_to_the_solid_angle() {
        let cap = Cap::new(DVec3::new(0.3, -0.5, 0.8), 0.7);
        for (a, b) in [(0.1, 0.2), (0.9, 0.95), (0.5, 0.0)] {
            let (a2, b2) = cap.coords(cap.direction(a, b) * 3.0).unwrap();
            assert!((a - a2).abs() < 1e-12 && ((b - b2 + 0.5).rem_euclid(1.0) - 0.5).abs() < 1e-12);
        }
        assert!(cap.coords(-cap.frame[2]).is_none());
        let area = integrate_cell(&cap.density(|_| 1.0), [0.0, 1.0], [0.0, 1.0], 4);
        assert!((area / (2.0 * PI * (1.0 - 0.7f64.cos())) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn chi2_accepts_the_right_distribution_and_rejects_a_wrong_one() {
        // A discrete distribution sampled with the kernel's own stream.
        let p = [0.5, 0.25, 0.125, 0.0625, 0.0625, 0.0];
        let n = 200_000;
        let mut rng = Sampler::new(1, 2, 3);
        let mut obs = [0.0; 6];
        for _ in 0..n {
            let u = f64::from(rng.next_f32());
            let mut acc = 0.0;
            let i = p.iter().position(|&pi| {
                acc += pi;
                u < acc
            });
            obs[i.unwrap_or(4)] += 1.0;
        }
        let exp: Vec<f64> = p.iter().map(|pi| pi * n as f64).collect();
        let ok = chi2_pooled(&obs, &exp).unwrap();
        assert!(ok.p_value > 1e-3, "{ok:?}");
        assert_eq!(ok.dof, 4);
        // 1% of the mass moved from one cell to another is detected.
        let mut wrong = exp.clone();
        wrong[0] -= 0.01 * n as f64;
        wrong[1] += 0.01 * n as f64;
        assert!(chi2_pooled(&obs, &wrong).unwrap().p_value < 1e-10);
        // Samples where the pdf is zero are an error.
        let mut leak = obs;
        leak[5] = 10.0;
        assert!(chi2_pooled(&leak, &exp).is_err());
        // Sidak: 20 tests at a family-wise 1%.
        assert!((sidak(0.01, 20) - 5.024e-4).abs() < 1e-6);
    }

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
