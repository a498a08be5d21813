//! Property 1: `render_pixel` outputs are finite and non-negative everywhere, and the weight
//! sums of both techniques are within their bounds.

use crate::runner::{Tally, check_property, estimator};
use crate::scenes::{build, scene_spec, settings};
use picomis::{Estimate, LightSelection, Method, RenderSettings, Rgb};
use proptest::prelude::*;
use proptest::test_runner::TestCaseResult;

pub fn finite_non_negative(c: Rgb) -> bool {
    c.is_finite() && c.min_element() >= 0.0
}

/// `lights`: how many lights the scene has (a light sample of the selection `every` is one
/// sample of each).
fn check_estimate(
    e: &Estimate,
    settings: &RenderSettings,
    lights: u16,
    at: (u32, u32),
    tally: &Tally,
) -> TestCaseResult {
    let (n_light, n_bsdf) = settings.technique_samples();
    let n_light =
        if settings.light_selection() == LightSelection::Every { n_light * lights } else { n_light };
    prop_assert!(finite_non_negative(e.emitted), "pixel {at:?}: emitted {}", e.emitted);
    prop_assert!(finite_non_negative(e.radiance()), "pixel {at:?}: radiance {}", e.radiance());
    let single = |m: Method| settings.method() == m;
    for (name, t, n, alone) in [
        ("light", &e.light, n_light, single(Method::LightOnly)),
        ("BSDF", &e.bsdf, n_bsdf, single(Method::BsdfOnly)),
    ] {
        prop_assert!(
            finite_non_negative(t.contribution),
            "pixel {at:?}: {name} contribution {}",
            t.contribution
        );
        prop_assert!(
            t.weight_sum.is_finite() && t.weight_sum >= 0.0 && t.weight_sum <= t.found as f32 * (1.0 + 1e-6),
            "pixel {at:?}: {name} weight sum {} over {} samples that found light",
            t.weight_sum,
            t.found
        );
        prop_assert!(
            t.found <= settings.spp() * u32::from(n),
            "pixel {at:?}: {name} found {} > spp x {n}",
            t.found
        );
        if alone {
            prop_assert_eq!(t.weight_sum, t.found as f32, "pixel {:?}: {} alone must weigh 1", at, name);
        }
        if t.found > 0 {
            tally.add(if name == "light" {
                "pixel lit by light samples"
            } else {
                "pixel lit by BSDF samples"
            });
        }
    }
    if e.radiance().max_element() > 0.0 {
        tally.add("pixel with radiance > 0");
    }
    Ok(())
}

#[test]
fn render_pixel_outputs_are_finite() {
    let tally = Tally::default();
    check_property(3000, (scene_spec(), settings()), |(spec, settings)| {
        let Some(scene) = build(&spec, 6, 4) else { return Ok(()) };
        tally.add("scene");
        let it = estimator(&scene, &settings)?;
        for y in 0..4 {
            for x in 0..6 {
                let lights = scene.lights().len() as u16;
                check_estimate(&it.render_pixel(x, y), &settings, lights, (x, y), &tally)?;
            }
        }
        Ok(())
    });
    tally.require(&[
        ("scene", 2900),
        ("pixel with radiance > 0", 9000),
        ("pixel lit by light samples", 4000),
        ("pixel lit by BSDF samples", 400),
    ]);
}
