//! Property tests of the MIS weights (`Heuristic::weights`, `Method::weight`) over random
//! q = n p arrays of 2 and 3 techniques, including 0, infinity, f32::MAX, subnormals, NaN and
//! negative values (documented to count as 0), for every heuristic with random parameters:
//!
//! - W1: the weights sum to 1 wherever some q_i > 0; W2: w_i = 0 wherever q_i is not > 0;
//! - every weight is finite and in [0, 1]; all weights are 0 when no q_i is positive;
//! - each heuristic's own formula, against an f64 reference computed from the same q;
//! - invariance under scaling all q by a common factor; monotonicity for balance and power.

use picomis::{Heuristic, Method, Technique};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

/// A q value: mostly log-uniform positives over the whole f32 range, plus every special case.
fn q_value() -> impl Strategy<Value = f32> {
    prop_oneof![
        6 => (-44.0f64..38.5).prop_map(|e| 10f64.powf(e) as f32),
        2 => 0.5f32..2.0,
        1 => Just(0.0f32),
        1 => Just(f32::INFINITY),
        1 => Just(f32::MAX),
        1 => Just(f32::MIN_POSITIVE),
        1 => Just(f32::from_bits(1)), // smallest subnormal
        1 => Just(1.0f32),
        1 => Just(f32::NAN),
        1 => Just(-1.0f32),
        1 => Just(-0.0f32),
        1 => Just(f32::NEG_INFINITY),
        1 => proptest::num::f32::POSITIVE | proptest::num::f32::SUBNORMAL | proptest::num::f32::INFINITE,
    ]
}

fn heuristic() -> impl Strategy<Value = Heuristic> {
    prop_oneof![
        Just(Heuristic::Average),
        Just(Heuristic::Balance),
        Just(Heuristic::Power { beta: 2.0 }),
        Just(Heuristic::Power { beta: 3.0 }),
        (0.05f32..10.0).prop_map(|beta| Heuristic::Power { beta }),
        Just(Heuristic::Maximum),
        Just(Heuristic::Cutoff { alpha: 0.1 }),
        (0.0f32..=1.0).prop_map(|alpha| Heuristic::Cutoff { alpha }),
        Just(Heuristic::Cutoff { alpha: 0.0 }),
        Just(Heuristic::Cutoff { alpha: 1.0 }),
    ]
}

fn positive(q: f32) -> bool {
    q > 0.0
}

/// The ratios r_i = q_i / q_max (infinite entries: 1, finite ones: 0 when some q is infinite),
/// or `None` when no q is positive. The division is done in f32 as the kernel does it (so a
/// ratio that underflows, or rounds to a subnormal, is the kernel's), then widened to f64.
fn ratios<const N: usize>(q: [f32; N]) -> Option<[f64; N]> {
    let q = q.map(|v| if positive(v) { v } else { 0.0 });
    let max = q.iter().cloned().fold(0.0, f32::max);
    if max <= 0.0 {
        return None;
    }
    let r =
        if max.is_finite() { q.map(|v| v / max) } else { q.map(|v| if v.is_infinite() { 1.0 } else { 0.0 }) };
    Some(r.map(f64::from))
}

/// The weights of `h` in f64, from the ratios.
fn reference<const N: usize>(h: Heuristic, r: [f64; N]) -> [f64; N] {
    let norm = |x: [f64; N]| {
        let s: f64 = x.iter().sum();
        x.map(|v| v / s)
    };
    match h {
        Heuristic::Average => norm(r.map(|v| if v > 0.0 { 1.0 } else { 0.0 })),
        Heuristic::Balance => norm(r),
        Heuristic::Power { beta } => norm(r.map(|v| v.powf(f64::from(beta)))),
        Heuristic::Maximum => {
            let i = r.iter().position(|&v| v >= 1.0).unwrap();
            let mut w = [0.0; N];
            w[i] = 1.0;
            w
        }
        Heuristic::Cutoff { alpha } => norm(r.map(|v| if v >= f64::from(alpha) { v } else { 0.0 })),
    }
}

fn check_weights<const N: usize>(h: Heuristic, q: [f32; N]) -> Result<(), TestCaseError> {
    let w = h.weights(q);
    for (&wi, &qi) in w.iter().zip(&q) {
        prop_assert!(wi.is_finite() && (0.0..=1.0).contains(&wi), "{h:?} {q:?} -> {w:?}");
        // W2: no weight where the technique cannot produce the sample.
        if !positive(qi) {
            prop_assert_eq!(wi, 0.0, "W2 broken: {:?} {:?} -> {:?}", h, q, w);
        }
    }
    let Some(r) = ratios(q) else {
        prop_assert_eq!(w, [0.0; N], "no positive q must give no weight");
        return Ok(());
    };
    // W1: a partition of unity.
    let sum: f64 = w.iter().map(|&v| f64::from(v)).sum();
    prop_assert!((sum - 1.0).abs() <= 1e-6, "W1 broken: {h:?} {q:?} -> {w:?} (sum {sum})");
    // The heuristic's own formula. A cutoff whose ratio sits within rounding of alpha may go
    // either way: skip those.
    if let Heuristic::Cutoff { alpha } = h {
        if r.iter().any(|&v| v > 0.0 && (v / f64::from(alpha) - 1.0).abs() < 1e-5) {
            return Ok(());
        }
    }
    let e = reference(h, r);
    for (i, (&wi, &ei)) in w.iter().zip(&e).enumerate() {
        prop_assert!((f64::from(wi) - ei).abs() <= 2e-5, "{h:?} {q:?}: w[{i}] = {wi}, expected {ei} ({w:?})");
    }
    // Maximum: one technique takes everything.
    if h == Heuristic::Maximum {
        prop_assert_eq!(w.iter().filter(|&&v| v == 1.0).count(), 1);
    }
    Ok(())
}

fn check_scaling<const N: usize>(h: Heuristic, q: [f32; N], scale: f32) -> Result<(), TestCaseError> {
    // Only where neither q nor scale * q leaves a range in which no ratio q_i / q_max can
    // underflow f32.
    let ok = |v: f32| v == 0.0 || (1e-15..1e15).contains(&v);
    let scaled = q.map(|v| v * scale);
    if !q.iter().chain(&scaled).all(|&v| ok(v)) {
        return Ok(());
    }
    let (a, b) = (h.weights(q), h.weights(scaled));
    for (x, y) in a.iter().zip(&b) {
        let tol = match h {
            Heuristic::Maximum | Heuristic::Average => 0.0,
            _ => 1e-4,
        };
        if matches!(h, Heuristic::Cutoff { .. }) {
            // A ratio within rounding of the cutoff may be kept on one side and dropped on the
            // other; the weights must still agree wherever both keep the same set.
            let kept = |w: &[f32; N]| w.map(|v| v > 0.0);
            if kept(&a) != kept(&b) {
                return Ok(());
            }
        }
        if matches!(h, Heuristic::Maximum) && q.iter().filter(|&&v| v > 0.0).count() > 1 {
            // Ties broken by rounding of the scaled values may move the maximum.
            let mx = q.iter().cloned().fold(0.0f32, f32::max);
            if q.iter().filter(|&&v| v >= mx * 0.999_99).count() > 1 {
                return Ok(());
            }
        }
        prop_assert!((x - y).abs() <= tol, "{h:?}: {q:?} -> {a:?}, scaled by {scale} -> {b:?}");
    }
    Ok(())
}

fn check_monotone<const N: usize>(h: Heuristic, q: [f32; N]) -> Result<(), TestCaseError> {
    if !matches!(h, Heuristic::Balance | Heuristic::Power { .. }) {
        return Ok(());
    }
    let w = h.weights(q);
    for i in 0..N {
        for j in 0..N {
            let (qi, qj) = (if positive(q[i]) { q[i] } else { 0.0 }, if positive(q[j]) { q[j] } else { 0.0 });
            if qi > qj {
                prop_assert!(w[i] >= w[j], "{h:?}: q {q:?} -> w {w:?}");
            }
        }
    }
    Ok(())
}

fn check_method(h: Heuristic, q_light: f32, q_bsdf: f32) -> Result<(), TestCaseError> {
    let m = Method::Mis(h);
    let (wl, wb) = (m.weight(Technique::Light, q_light, q_bsdf), m.weight(Technique::Bsdf, q_light, q_bsdf));
    prop_assert_eq!([wl, wb], h.weights([q_light, q_bsdf]));
    if positive(q_light) || positive(q_bsdf) {
        prop_assert!((wl + wb - 1.0).abs() <= 1e-6);
    }
    for (single, light, bsdf) in [(Method::LightOnly, 1.0, 0.0), (Method::BsdfOnly, 0.0, 1.0)] {
        prop_assert_eq!(single.weight(Technique::Light, q_light, q_bsdf), light);
        prop_assert_eq!(single.weight(Technique::Bsdf, q_light, q_bsdf), bsdf);
    }
    Ok(())
}

proptest! {
    // A fixed seed: the same 20,000 cases on every run (no flakiness; PROPTEST_RNG_SEED is ignored).
    #![proptest_config(ProptestConfig {
        cases: 20_000,
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(0x5EED_4D15),
        ..ProptestConfig::default()
    })]

    #[test]
    fn weights_of_two_techniques(h in heuristic(), q in [q_value(), q_value()]) {
        check_weights(h, q)?;
        check_monotone(h, q)?;
    }

    #[test]
    fn weights_of_three_techniques(h in heuristic(), q in [q_value(), q_value(), q_value()]) {
        check_weights(h, q)?;
        check_monotone(h, q)?;
    }

    #[test]
    fn weights_ignore_a_common_scale(
        h in heuristic(),
        q2 in [q_value(), q_value()],
        q3 in [q_value(), q_value(), q_value()],
        scale in (-3.0f64..3.0).prop_map(|e| 10f64.powf(e) as f32),
    ) {
        check_scaling(h, q2, scale)?;
        check_scaling(h, q3, scale)?;
    }

    #[test]
    fn methods_weigh_their_techniques(h in heuristic(), q_light in q_value(), q_bsdf in q_value()) {
        check_method(h, q_light, q_bsdf)?;
    }
}

/// Hand-picked corner cases (also run by the properties, but named here).
#[test]
fn corner_cases() {
    let all = picomis_tests::heuristics();
    let inf = f32::INFINITY;
    for &h in &all {
        for q in [
            [0.0, 0.0, 0.0],
            [inf, inf, inf],
            [inf, 1.0, 0.0],
            [f32::MAX, f32::MAX, 1.0],
            [f32::from_bits(1), 0.0, 0.0],
            [f32::from_bits(1), f32::MAX, 0.0],
            [f32::NAN, 1.0, -3.0],
            [1e30, 1e-30, 1.0],
        ] {
            check_weights(h, q).unwrap();
        }
        check_weights(h, [inf, 0.0]).unwrap();
        check_weights(h, [0.0, f32::MIN_POSITIVE]).unwrap();
    }
    // Infinite q dominate: [inf, 1] -> [1, 0] for every heuristic.
    for &h in &all {
        assert_eq!(h.weights([inf, 1.0]), [1.0, 0.0], "{h:?}");
    }
}
