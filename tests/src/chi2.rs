//! Pearson's chi-square with Mitsuba's pooling of cells with fewer than 5 expected samples and a
//! Sidak-corrected significance level.

use statrs::distribution::{ChiSquared, ContinuousCDF};

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

#[cfg(test)]
mod tests {
    use super::*;
    use picomis::Sampler;

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
}
