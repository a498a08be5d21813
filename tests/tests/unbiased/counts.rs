//! Multi-sample counts: n_light = 2, n_bsdf = 3 and the reverse; no BSDF samples; no light
//! samples.

use crate::harness::{check_methods, lambert_out, methods, scaled, sphere_e};
use crate::lambertian::{SPHERE_L, sphere_scene};
use crate::several_lights::many_lights;
use picomis::{Heuristic, LightSelection, Method, SphereSampling};

#[test]
fn multi_sample_counts() {
    let (scene, exact) = many_lights();
    let power2 = vec![("MIS power 2".to_string(), Method::Mis(Heuristic::Power { beta: 2.0 }))];
    let all_mis: Vec<(String, Method)> =
        methods().into_iter().filter(|(_, m)| matches!(m, Method::Mis(_))).collect();
    let light_only = vec![("light only".to_string(), Method::LightOnly)];
    let bsdf_only = vec![("BSDF only".to_string(), Method::BsdfOnly)];
    let (sel, cone) = (LightSelection::Power, SphereSampling::Cone);
    // n_light = 2, n_bsdf = 3 (every heuristic sees q_i = n_i p_i).
    check_methods("(counts) four lights", &scene, &all_mis, (2, 3), cone, sel, exact, 8000);
    check_methods("(counts) four lights", &scene, &power2, (3, 2), SphereSampling::Area, sel, exact, 8100);
    // No BSDF samples: MIS degenerates to light sampling (weight 1); and no light samples.
    check_methods("(counts) four lights", &scene, &all_mis, (1, 0), cone, sel, exact, 8200);
    check_methods("(counts) four lights", &scene, &light_only, (4, 0), cone, sel, exact, 8300);
    check_methods("(counts) four lights", &scene, &all_mis, (0, 2), cone, sel, exact, 8400);
    check_methods("(counts) four lights", &scene, &bsdf_only, (0, 4), cone, sel, exact, 8500);
    let (sphere, c) = sphere_scene(60.0, 1.0, 3.0);
    let exact = lambert_out(scaled(SPHERE_L, sphere_e(c, 1.0)));
    check_methods("(counts) sphere at 60 deg", &sphere, &power2, (2, 3), cone, sel, exact, 8600);
}
