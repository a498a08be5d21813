//! Unbiasedness of every direct-lighting method against closed forms.
//!
//! Each check draws N independent estimates (estimate i from `Sampler::new(seed, stream, i)`)
//! at a hand-built shading point through the estimator's `estimate_direct` (or `trace` for a
//! camera ray; `picomis_host::renderer`, in the host's scene type), and asserts
//! |mean - exact| < z_max stderr per colour channel with stderr < 2% of the exact value, so that
//! every check can fail. z_max (5.1) is the suite's family-wise threshold: its 3,159 z-tests
//! together fail by chance on at most 1 in 1,000 draws of their streams (Bonferroni;
//! `harness::z_max`); at 4 on each, one would fail on about a fifth of them. `power.rs` shows
//! what the checks can see: a 1 % bias at a Lambertian receiver and 2 % on Veach's glossy plates. Methods: light sampling only, BSDF sampling only, and MIS with every
//! heuristic (average, balance, power 2, 3 and 0.5, maximum, cutoff 0.1); sphere lights sampled
//! by area and by cone; light selection uniform, by power and by contribution.
//!
//! Cases: (a) a Lambertian plane under a sphere light (theta 0 and 60 degrees); (b) a quad light
//! (Lambert's polygon formula); (c) the furnace: an open box of five emitting walls over a
//! Lambertian floor, L = rho Le, where BSDF sampling has zero variance; (d) a point light plus a
//! sphere light (BSDF sampling cannot see the point light: it gets exactly the sphere's part);
//! (e) lights of different power; (f) a GGX conductor under a sphere light, against an adaptive
//! quadrature of the kernel's `Material::eval` over the light's cone (no closed form for GGX);
//! (g) the same GGX floor (alpha 0.05 and 0.3) under three sphere lights, one near the mirror
//! direction, with every light selection (contribution weighs the lights by the BSDF);
//! plus multi-sample counts (n_light = 2, n_bsdf = 3; n_bsdf = 0; n_light = 0) and the
//! determinism of camera rendering. Every check of (a)-(h) and the counts runs with every sample
//! stream ([`SamplerKind`](picomis::SamplerKind)); with sobol the N estimates of a check are 32
//! independent scrambles of N/32 (`picomis_tests::direct_run`), and the standard error is their
//! spread (Student's t with 31 degrees of freedom), not the independent-sample formula, which
//! overstates the error of a randomised quasi-Monte Carlo mean: on 2026-12-07 the 343 sobol checks
//! gave z of mean +0.07 and spread 1.01 (Student's t31: 1.03), the 343 independent ones +0.03
//! and 1.04.

mod counts;
mod determinism;
mod furnace;
mod glossy;
mod harness;
mod lambertian;
mod lobe_mixing;
mod power;
mod several_lights;
