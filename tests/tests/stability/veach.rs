//! Veach's bound on the balance heuristic: the check of every case's run (the table's last
//! column) and a test that the check can fail.

use crate::glossy::grazing_view_lambert;
use crate::harness::{Case, Check, Col, Reference, run};
use picomis::ControlVariate;
use picomis_tests::Stats;

/// Veach's bound on the balance heuristic, checked where its theorem applies, and the table's
/// cell saying what was checked. The theorem compares combinations of the same techniques (the
/// same pdfs p_i) with the same sample counts n_i: here the other heuristics, and each of the two
/// techniques alone, the combination that gives the other technique's sample weight 0 (a valid
/// weighting where that technique alone converges, its variance that of the technique alone).
/// Not "light (area)": where the case has a sphere light, its light technique is another one. Not
/// with the control variate: there the techniques combine f (V - 1), whose integral is not the
/// case's reference. Where balance's own variance is within c mu^2 (to 4 of its standard errors),
/// V[balance] - V[other] cannot exceed c mu^2 for any other method: the check cannot fail, and the
/// cell says so.
pub fn veach_bound_cell(
    case: &Case,
    reference: f64,
    totals: &[(Col, Check, Stats)],
    notes: &mut Vec<String>,
    failures: &mut Vec<String>,
) -> String {
    let label = &case.label;
    let converges = |c: Check| matches!(c, Check::Total | Check::ZeroVariance);
    let Some(&(_, bal_check, balance)) = totals.iter().find(|(c, ..)| *c == Col::Balance) else {
        return "n/a".into();
    };
    if reference == 0.0 || !converges(bal_check) {
        return "n/a".into();
    }
    if case.control_variate == ControlVariate::On {
        return "n/a (control variate)".into();
    }
    let mu2 = reference * reference;
    let others: Vec<&(Col, Check, Stats)> = totals
        .iter()
        .filter(|(c, k, _)| !matches!(c, Col::Balance | Col::LightArea) && converges(*k))
        .collect();
    let mut worst = f64::NEG_INFINITY;
    for (col, _, other) in &others {
        let name = format!("{label}, Veach's bound, balance vs {}", col.name());
        match check_veach_bound(&name, &balance, other, reference, VEACH_BOUND) {
            Ok(z) => worst = worst.max(z),
            Err(e) => failures.push(e),
        }
    }
    let rel = balance.variance() / mu2;
    let can_fail = balance.variance() - VEACH_BOUND * mu2 > 4.0 * balance.variance_stderr() + 1e-9 * mu2;
    notes.push(format!(
        "{label}: Veach's bound against {} methods, largest z = {worst:.2}; balance's relative variance \
         {rel:.2e} {} the bound's {VEACH_BOUND}",
        others.len(),
        if can_fail { "above" } else { "within" }
    ));
    match (others.is_empty(), can_fail) {
        (true, _) => "n/a".into(),
        (false, true) => format!("z ≤ {worst:.1}"),
        (false, false) => "cannot fail".into(),
    }
}

/// Veach's bound factor (1 / min_i n_i - 1 / sum_i n_i) for sample counts `n`.
fn veach_bound(n: &[f64]) -> f64 {
    1.0 / n.iter().copied().fold(f64::INFINITY, f64::min) - 1.0 / n.iter().sum::<f64>()
}

/// Veach's bound for one light and one BSDF sample: 1/2.
const VEACH_BOUND: f64 = 0.5;

/// Veach's bound (Veach and Guibas 1995, theorem 1; Veach 1997, theorem 9.2) as a one-sided z-test: V[F_balance] - V[F_other] <= c mu^2
/// for any other weighting with the same sample counts, from the two runs' sample variances.
/// The runs are independent, so the variance of the difference is the sum of the variances of
/// the two sample variances, each from its fourth moment ([`Stats::variance_stderr`]). Fails when
/// the excess is more than 4 standard errors above c mu^2. Returns the excess in standard errors.
fn check_veach_bound(name: &str, balance: &Stats, other: &Stats, mu: f64, c: f64) -> Result<f64, String> {
    let excess = balance.variance() - other.variance() - c * mu * mu;
    let se = balance.variance_stderr().hypot(other.variance_stderr());
    let z = if se > 0.0 { excess / se } else { excess.signum() * f64::INFINITY };
    if excess <= 4.0 * se + 1e-9 * mu * mu {
        Ok(z)
    } else {
        Err(format!(
            "{name}: V[balance] - V[other] = {:.4e} mu^2 exceeds the bound {c} mu^2 by {z:.1} standard errors \
             (V[balance] = {:.4e} ± {:.1e}, V[other] = {:.4e} ± {:.1e}, mu = {mu:.4e})",
            (balance.variance() - other.variance()) / (mu * mu),
            balance.variance(),
            balance.variance_stderr(),
            other.variance(),
            other.variance_stderr()
        ))
    }
}

/// The bound check can fail: a wrong bound (c = 0: "balance is always best", which Veach's bound
/// does not claim in the multi-sample model) and a wrong weighting put in the balance heuristic's
/// place (the arithmetic average) are both caught at the grazing-view Lambertian case, where the
/// power heuristic beats balance and the average is far worse than both.
#[test]
fn veach_bound_check_can_fail() {
    assert_eq!(veach_bound(&[1.0, 1.0]), VEACH_BOUND);
    let case = grazing_view_lambert();
    let Reference::Exact(mu) = case.reference else { unreachable!("the case has a closed form") };
    let total =
        |col: Col, k: u32| run(&case, &col.settings(case.selection), 16 * 900 + k, case.n).unwrap().total;
    let (balance, power, average) = (total(Col::Balance, 0), total(Col::Power, 1), total(Col::Average, 2));
    let name = "grazing view";
    let z = check_veach_bound(name, &balance, &power, mu, VEACH_BOUND).unwrap();
    println!("balance vs power, true bound: z = {z:.2}");
    let wrong_bound = check_veach_bound(name, &balance, &power, mu, 0.0);
    println!("balance vs power, c = 0: {wrong_bound:?}");
    assert!(wrong_bound.is_err(), "a bound of 0 must fail where power beats balance");
    let wrong_weights = check_veach_bound(name, &average, &power, mu, VEACH_BOUND);
    println!("average in balance's place: {wrong_weights:?}");
    assert!(wrong_weights.is_err(), "the average in balance's place must fail the bound");
}
