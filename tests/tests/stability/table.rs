//! The table of relative variances: its legend, its markdown, the rows every group adds (written
//! to the file named by `PICOMIS_STABILITY_TABLE`), and the check that docs/stability.md holds
//! a run's rows verbatim.

use crate::harness::COLS;
use std::fmt::Write as _;
use std::sync::Mutex;

const LEGEND: &str = "Relative variance Var[F] / ref^2 of one estimate F (one light and one BSDF sample; \
light-only and BSDF-only methods draw only their own sample), at the shading point of each case \
(for the cases at 16 camera-ray hits, the spread of the value across the hits is included). \
Plain numbers: the mean was asserted equal to the reference (|z| < 4, the independent-sample \
standard error, conservative for the sobol stream; stderr < 2%). \
`†`: the method cannot reach the expectation at these sample counts: finiteness asserted, the \
mean not (`×m`: the mean was m times the reference); these are sample variances of heavy-tailed \
estimators, far below the true ones. `no hit`: not one of its samples found light. `½`: the \
average heuristic is unbiased, but it gives each technique half of f, and one of the two \
techniques (rarely or never) finds the light at these sample counts: only the other technique's \
half (0.5 ref) was asserted, not the total. `‡`: the method converges to another value by design (BSDF sampling cannot find \
point lights), asserted. `refused`: the kernel refuses the control variate without light samples \
(its closed form is the light technique's part), asserted. Rows whose reference is exactly 0: every \
estimate of every method was exactly 0 and no sample found light. Veach's bound (Veach 1997, \
theorem 9.2): V[balance] - V[other] <= (1/min n_i - 1/sum n_i) mu^2 = mu^2 / 2 for one light and one BSDF \
sample, checked (one-sided, 4 standard errors of the two sample variances) against the other \
heuristics and each technique alone (the combinations of the same two techniques with the same \
sample counts), wherever they converge; not against light (area), another light technique. `z ≤ x`: \
it held, x the largest excess over mu^2 / 2 in standard errors. `cannot fail`: balance's own \
relative variance is below 1/2 (within 4 standard errors), so no method's variance can make the \
difference exceed the bound. `n/a`: no other method converges, the reference is 0 or balance \
does not converge; `n/a (control variate)`: the techniques combine f (V - 1), whose integral is \
not the reference.";

pub fn table(rows: &[(u32, String)]) -> String {
    let mut t = String::new();
    let names: Vec<&str> = COLS.iter().map(|c| c.name()).collect();
    let _ = writeln!(t, "| case | reference | N | {} | Veach's bound |", names.join(" | "));
    let _ = writeln!(t, "|---|---|---:|{}---|", "---:|".repeat(COLS.len()));
    for (_, row) in rows {
        let _ = writeln!(t, "{row}");
    }
    let _ = writeln!(t, "\n{LEGEND}");
    t
}

/// The committed table (docs/stability.md) must hold this run's rows verbatim: the
/// runs are deterministic, so a change that alters a figure fails here until the tables are
/// regenerated (`PICOMIS_STABILITY_TABLE`, module docs).
pub fn stale_rows(rows: &[(u32, String)]) -> Vec<String> {
    let rows: Vec<&str> = rows.iter().map(|(_, r)| r.as_str()).collect();
    stale_in(&["docs/stability.md"], &rows)
}

/// The rows of `rows` that a line of one of `docs` (paths from the repository root) does not
/// hold verbatim, as failures.
pub fn stale_in(docs: &[&str], rows: &[&str]) -> Vec<String> {
    let mut stale = Vec::new();
    for doc in docs {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(doc);
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        for row in rows {
            if !text.lines().any(|l| l == *row) {
                stale.push(format!("{doc} does not have this run's row (regenerate it): {row}"));
            }
        }
    }
    stale
}

/// Every row finished so far, with its case id.
static TABLE: Mutex<Vec<(u32, String)>> = Mutex::new(Vec::new());

/// Adds a group's rows to the table of every row finished so far and, where
/// `PICOMIS_STABILITY_TABLE` names a file, rewrites it with them (in case order).
pub fn record(rows: Vec<(u32, String)>) {
    let mut all = TABLE.lock().unwrap_or_else(|e| e.into_inner());
    all.extend(rows);
    all.sort_by_key(|(id, _)| *id);
    if let Some(path) = std::env::var_os("PICOMIS_STABILITY_TABLE") {
        std::fs::write(&path, table(&all)).expect("write the stability table");
    }
}
