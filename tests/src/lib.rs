//! Shared helpers of the statistical test suites of picomis (the suites are in `tests/tests/*.rs`),
//! one module per part, all re-exported here:
//!
//! - [`stats`]: [`Stats`], running mean and standard error (Welford, f64), and [`assert_unbiased`] /
//!   [`check_unbiased`], the z-test every unbiasedness check goes through (|mean - exact| <
//!   4 stderr, and the stderr must be small enough for the check to be able to fail), with
//!   [`check_agreement`] for two estimates of a value that has no closed form; [`MeanEstimate`]
//!   and [`check_mean`], the same test for a standard error with few degrees of freedom (the
//!   spread of independent scrambles: Student's t at the level of 4 sigma, [`z_threshold`]);
//! - [`chi2`](mod@chi2): [`chi2_pooled`] / [`assert_chi2`], Pearson's chi-square with Mitsuba's
//!   pooling of cells with fewer than 5 expected samples and a Sidak-corrected significance level;
//! - [`histogram`](mod@histogram): [`Histogram2d`], a chart of the sample space on [0, 1)^2 binned
//!   into cells, whose expected counts come from integrating a density numerically (adaptive
//!   Gauss-Legendre per cell);
//! - [`cap`]: [`Cap`], a polar chart of (part of) the sphere of directions around an axis;
//! - [`closed_forms`]: [`sphere_irradiance`], [`sphere_irradiance_at`],
//!   [`lambert_polygon_irradiance`], [`polygon_solid_angle`], [`cone_measure`];
//! - [`scenes`]: scene builders [`camera`], [`quad_corners`], [`shading_hit`], and
//!   [`direct_stats`], [`heuristics`] (in the host's scene type, [`picomis_host::HostScene`]:
//!   their settings are chosen at run time); [`direct_run`] and [`trace_run`], which split a
//!   sobol run into [`SCRAMBLES`] independent scrambles so that its standard error is that of
//!   randomised quasi-Monte Carlo ([`RunStats::estimate`]), not the independent-sample formula;
//! - [`strategies`]: [`LightChoices`], light strategies named at run time, and
//!   [`LightChoices::visit`], which calls a [`VisitLights`] with them as types (the kernel's light
//!   sampler is generic over them).
//!
//! Tests are host code: everything here computes in f64 (glam's [`DVec3`]) unless it calls the
//! kernel.

pub mod cap;
pub mod chi2;
pub mod closed_forms;
pub mod histogram;
pub mod scenes;
pub mod stats;
pub mod strategies;

pub use cap::*;
pub use chi2::*;
pub use closed_forms::*;
pub use glam::DVec3;
pub use histogram::*;
pub use scenes::*;
pub use stats::*;
pub use strategies::*;
