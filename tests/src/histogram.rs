//! Histograms of samples charted on [0, 1)^2 ([`Histogram2d`]) whose expected counts come from
//! integrating a density numerically (adaptive Gauss-Legendre per cell), tested with the pooled
//! chi-square.

use picomis::{Sampler, Vec2};

use crate::chi2::{Chi2, assert_chi2};

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
