//! The budget check: measured figures against budget.json.

use std::io::{self, Write};

use super::error::Error;
use super::figures::Figures;
use super::keys::{Key, TOLERANCE_PERCENT, budget_keys};

/// What the check says of one figure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Verdict {
    /// Within the tolerance, and not across a target it met.
    Within,
    /// More than [`TOLERANCE_PERCENT`] above the committed figure.
    AboveTolerance,
    /// The committed figure met its target (a ceiling then) and the measured one crosses it,
    /// even if within the tolerance.
    CrossesTarget(u32),
}

/// The rule for one figure: `committed` from budget.json, `measured` now, the figure's target.
pub fn judge(committed: f64, measured: f64, target: Option<u32>) -> Verdict {
    if measured > committed * (1.0 + f64::from(TOLERANCE_PERCENT) / 100.0) {
        return Verdict::AboveTolerance;
    }
    match target {
        Some(t) if committed <= f64::from(t) && measured > f64::from(t) => Verdict::CrossesTarget(t),
        _ => Verdict::Within,
    }
}

/// Every budget figure of `measured` against `budget`, one line each on `out`; fails on the first
/// figure missing from either, and after all lines if any figure is over.
pub fn check(budget: &Figures, measured: &Figures, out: &mut impl Write) -> Result<(), Error> {
    let rows = budget_keys()
        .into_iter()
        .map(|key| Ok((key, budget.get(key)?, measured.get(key)?)))
        .collect::<Result<Vec<_>, Error>>()?;
    let mut over = false;
    for (key, committed, now) in rows {
        let line = match judge(committed.value, now.value, key.target()) {
            Verdict::AboveTolerance => {
                format!(
                    "OVER  {:<49} {:>12} > {} + {TOLERANCE_PERCENT} %",
                    name(key),
                    now.text,
                    committed.text
                )
            }
            Verdict::CrossesTarget(target) => {
                format!("OVER  {:<49} {:>12} > the target {target}", name(key), now.text)
            }
            Verdict::Within => {
                format!("ok    {:<49} {:>12} (committed {})", name(key), now.text, committed.text)
            }
        };
        over |= line.starts_with("OVER");
        writeln!(out, "{line}").map_err(stdout_error)?;
    }
    if over {
        return Err(Error::OverBudget);
    }
    writeln!(out, "firmware figures within {TOLERANCE_PERCENT} % of firmware/budget.json")
        .map_err(stdout_error)
}

fn name(key: Key) -> String {
    key.to_string()
}

fn stdout_error(source: io::Error) -> Error {
    Error::Io { path: "(standard output)".into(), source }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::budget::figures::without_key;
    use std::path::Path;

    const FIGURES: &str = include_str!("../../fixtures/budget/figures_mixed.txt");

    #[test]
    fn two_percent_rule() {
        assert_eq!(judge(1000.0, 1020.0, None), Verdict::Within);
        assert_eq!(judge(1000.0, 1020.5, None), Verdict::AboveTolerance);
        assert_eq!(judge(1000.0, 900.0, None), Verdict::Within);
        // Over its target before and still: only the tolerance holds it.
        assert_eq!(judge(2100.0, 2140.0, Some(2000)), Verdict::Within);
        assert_eq!(judge(2100.0, 2143.0, Some(2000)), Verdict::AboveTolerance);
    }

    #[test]
    fn target_crossing_rule() {
        // Within its target before: the target is a ceiling, even within the tolerance.
        assert_eq!(judge(1990.0, 2000.0, Some(2000)), Verdict::Within);
        assert_eq!(judge(1990.0, 2001.0, Some(2000)), Verdict::CrossesTarget(2000));
        assert_eq!(judge(2000.0, 2000.5, Some(2000)), Verdict::CrossesTarget(2000));
        assert_eq!(judge(1990.0, 2001.0, None), Verdict::Within);
    }

    /// The check's output: the shell version of scripts/budget.sh's `check` (with its target
    /// lookup's exit status fixed, fixtures/budget/README.md) of figures_*.txt against
    /// budget_mixed.json.
    const CHECK_MIXED: &str = include_str!("../../fixtures/budget/check_mixed.txt");
    const OVER: &str = include_str!("../../fixtures/budget/figures_over.txt");
    const CHECK_OVER: &str = include_str!("../../fixtures/budget/check_over.txt");

    fn run(measured: &str) -> (Result<(), Error>, String) {
        let json = include_str!("../../fixtures/budget/budget_mixed.json");
        let budget = Figures::from_budget_json(Path::new("budget.json"), json).unwrap();
        let measured = Figures::from_lines(Path::new("figures.txt"), measured).unwrap();
        let mut out = Vec::new();
        let result = check(&budget, &measured, &mut out);
        (result, String::from_utf8(out).unwrap())
    }

    #[test]
    fn the_committed_figures_pass() {
        let (result, out) = run(FIGURES);
        assert!(result.is_ok());
        assert_eq!(out, CHECK_MIXED);
        assert_eq!(out.lines().count(), budget_keys().len() + 1);
    }

    #[test]
    fn a_rise_or_a_crossing_fails() {
        // m0_static_ram_bytes 3688 -> 3762 (2.01 %), m0_best_instructions_per_camera_sample
        // 19876.5 -> 20000.5 (0.6 %, across its target), m4f_peak_stack_bytes 2256 -> 2301
        // (1.99 %: within).
        let (result, out) = run(OVER);
        assert!(matches!(result, Err(Error::OverBudget)));
        assert_eq!(out, CHECK_OVER);
        assert_eq!(out.matches("OVER").count(), 2);
        // 3761 is 1.98 % above: within.
        let (result, _) = run(&FIGURES.replace("m0_static_ram_bytes 3688", "m0_static_ram_bytes 3761"));
        assert!(result.is_ok());
    }

    #[test]
    fn missing_figure() {
        let (result, out) = run(&without_key(FIGURES, "rv32imc_peak_stack_bytes"));
        assert!(matches!(result, Err(Error::MissingFigure { key, .. }) if key == "rv32imc_peak_stack_bytes"));
        assert_eq!(out, "");
    }
}
