//! Running a property: proptest on a fixed ChaCha seed (no failure files), the estimator of a
//! random scene's settings, and the tally of what the cases exercised.

use crate::scenes::S;
use picomis::RenderSettings;
use picomis_host::{Renderer, renderer};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseResult, TestRng, TestRunner};
use std::cell::RefCell;
use std::collections::BTreeMap;

/// The estimator of `settings` on `scene` (the host's, for the strategies the settings name).
pub fn estimator<'a>(
    scene: &'a S,
    settings: &'a RenderSettings,
) -> Result<Box<dyn Renderer + 'a>, TestCaseError> {
    renderer(scene, settings).map_err(|e| TestCaseError::fail(format!("{settings:?}: {e}")))
}

/// Runs `test` on `cases` values of `strategy` drawn from a fixed ChaCha seed (no failure
/// files, `PROPTEST_*` variables have no say), and panics with the (shrunk) failing input.
pub fn check_property<T: Strategy>(cases: u32, strategy: T, test: impl Fn(T::Value) -> TestCaseResult)
where
    T::Value: std::fmt::Debug,
{
    if let Err(e) = run_property(cases, u32::MAX, strategy, test) {
        panic!("{e}");
    }
}

/// [`check_property`] returning the failure (after at most `shrink` shrinking steps) instead of
/// panicking: for the tests that show a property can fail.
pub fn run_property<T: Strategy>(
    cases: u32,
    shrink: u32,
    strategy: T,
    test: impl Fn(T::Value) -> TestCaseResult,
) -> Result<(), String>
where
    T::Value: std::fmt::Debug,
{
    let config = Config {
        cases,
        max_shrink_iters: shrink,
        failure_persistence: None,
        rng_algorithm: RngAlgorithm::ChaCha,
        ..Config::default()
    };
    let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &[0x57; 32]);
    TestRunner::new_with_rng(config, rng).run(&strategy, test).map_err(|e| e.to_string())
}

/// Counts of what the cases exercised, so that a property that checks nothing fails.
#[derive(Default)]
pub struct Tally(RefCell<BTreeMap<&'static str, u64>>);

impl Tally {
    pub fn add(&self, what: &'static str) {
        *self.0.borrow_mut().entry(what).or_default() += 1;
    }

    /// Asserts that every `(what, at_least)` happened often enough, and prints the counts.
    #[track_caller]
    pub fn require(&self, minimum: &[(&'static str, u64)]) {
        let counts = self.0.borrow();
        println!("{counts:?}");
        for &(what, at_least) in minimum {
            let n = counts.get(what).copied().unwrap_or(0);
            assert!(
                n >= at_least,
                "only {n} cases of '{what}' (at least {at_least} needed): the property is near vacuous"
            );
        }
    }
}
