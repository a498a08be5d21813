//! Every sampling routine of the kernel against its pdf.
//!
//! 1. Chi-square tests (Mitsuba style): 10^6 samples histogrammed on a chart of the sample space
//!    (a polar grid of directions, or the light's own surface), expected counts from integrating
//!    the kernel's pdf numerically over each cell, cells with < 5 expected pooled, significance
//!    0.01 Sidak-corrected over the [`CHI2_TESTS`] tests of this suite. Samplers that may return
//!    nothing get a "no sample" cell holding the pdf's missing mass.
//! 2. E[1/p(X)] = measure of the support (z < 4 on the standard error): hemisphere 2 pi, sphere
//!    4 pi, cone 2 pi (1 - cos theta_max) down to r/d = 1e-6, a sphere light's cone by area
//!    sampling, a quad light's solid angle (Van Oosterom-Strackee).

mod can_fail;
mod charts;
mod light_sampler;
mod materials;
mod measure;
mod one_light;
mod own_sampling;
mod routines;

/// Number of chi-square tests in this suite, every module's (for the Sidak correction).
const CHI2_TESTS: usize = 42;
/// Samples per chi-square test.
const N_CHI2: usize = 1_000_000;
/// Samples per E[1/p] test.
const N_MEASURE: usize = 200_000;
