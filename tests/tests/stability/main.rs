//! Failure cases of direct lighting: the configurations where one technique breaks
//! down, run through every method, with fixed seeds and z-score tolerances.
//!
//! Methods (the table's columns): BSDF sampling only; light sampling only with sphere lights
//! sampled by area and by cone; MIS (cone) with the average, balance, power 2, maximum and
//! cutoff 0.1 heuristics. One light and one BSDF sample per estimate; N estimates per method
//! (estimate i of method k draws from `Sampler::new(SEED, 16 * case + k, i)`).
//!
//! For every case and method:
//! - every estimate is finite (contributions and weight sums; mean and variance of the run);
//! - where the expectation is known it is asserted: |mean - ref| < 4 stderr with stderr < 2% of
//!   ref (`check_mean`), against a closed form, or, where none exists, against a reference
//!   run of MIS balance with 8 N estimates (`check_means`, combined standard error); the
//!   estimates are sobol's (the best preset's stream), taken as 32 independent scrambles
//!   (`direct_run_at`); the standard error is the independent-sample formula, which overstates
//!   the error of randomised quasi-Monte Carlo (conservative: the spread of the scrambles is
//!   sharper, and shows one discrepancy of 1e-3, noted in docs/stability.md);
//! - cases whose expectation is exactly 0 (light behind an occluder, shading point inside a
//!   one-sided sphere light, lights of zero radiance) require every estimate of every method to
//!   be exactly 0 and no sample to find light;
//! - a method that cannot reach the expectation at N (for instance BSDF sampling aiming at a
//!   light 1e-6 rad across, or light sampling aiming at a GGX lobe 1e-4 wide) is marked with
//!   the reason in its case; it is still required to be finite, and where a part of it can
//!   reach its share (the average heuristic gives each technique half of f) that part is
//!   asserted instead;
//! - the relative variance Var[F] / ref^2 of the per-estimate value is recorded.
//!
//! The variances form a markdown table, printed with `--nocapture` and written to the file
//! named by the environment variable `PICOMIS_STABILITY_TABLE` (each test rewrites the file
//! with every row finished so far, so it is complete once the whole suite has run):
//! `PICOMIS_STABILITY_TABLE=/tmp/stability.md cargo test --release -p picomis-tests --test
//! stability -- --nocapture` (a relative path is relative to `tests/`, where cargo runs the
//! suite). docs/stability.md holds one such table with a lesson per case; each group fails if a
//! row of its run is missing from it (the figures cannot go stale).
//!
//! Fixed point (`fixed_point_on_every_case`, module `fixed_point`): every case again with the
//! scene's ray queries in fixed point (`Arith::Fixed`), the study's fixed-point method (power
//! heuristic).
//! Either the format rejects the scene at build time with `SceneError::NotRepresentable`, naming
//! the shape that the format's rule (a sphere radius or quad edge below 2^-14 of the power of two
//! at or below the scene's extent) predicts, or every estimate is finite and its bias is measured
//! against the f32 path: the two runs take the same random numbers, so the mean of the paired
//! differences fixed - f32 and its standard error give a z-score (|mean difference| within 4
//! standard errors plus the suite's f32 rounding allowance asserted), and against the closed
//! form where the case has one. The table of those differences is printed with `--nocapture`
//! (`cargo test --release -p picomis-tests --test stability fixed_point -- --nocapture`);
//! docs/stability.md holds its rows, and the test fails if one is missing.

mod fixed_point;
mod glossy;
mod harness;
mod huge_lights;
mod near_mirrors;
mod occlusion;
mod point_lights;
mod quads;
mod scenes;
mod table;
mod tiny_lights;
mod veach;
