//! Golden image of a small render, and that render against its closed form.
//!
//! `lambert_sphere` is a Lambertian plane (albedo rho) under one sphere light (radius r,
//! radiance L, center at height h above the plane) that is fully above every plane point's
//! horizon, so the reflected radiance at a plane point at distance d from the center is, in
//! closed form (`picomis_tests::sphere_irradiance`, tests/src/closed_forms.rs), L_out = (rho / pi) * pi L (r/d)^2 cos(theta) = rho L r^2 h / d^3.
//!
//! The golden is `tests/data/lambert_sphere_32x24_64spp_seed0.pfm`, rendered by this binary. The
//! comparison is bit-exact: the kernel does all math in f32 through `libm` (software, no platform
//! intrinsics, no fast-math), and a pixel's random numbers depend only on the seed, the pixel and
//! the sample index, so neither threads nor tile order can change a bit. A change in the kernel's
//! arithmetic or sampling will change the golden on purpose: check the closed-form test still
//! passes, look at the image, then regenerate it with `PICOMIS_BLESS=1 cargo test -p picomis-sim
//! --test golden` and commit it.

mod common;

use std::path::{Path, PathBuf};

use common::run_ok;
use picomis_sim::output::{Image, read_pfm};

const W: u32 = 32;
const H: u32 = 24;

fn golden_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/lambert_sphere_32x24_64spp_seed0.pfm")
}

fn render(dir: &Path, name: &str, extra: &[&str]) -> Image {
    let (w, h) = (W.to_string(), H.to_string());
    let mut args = vec!["render", "lambert_sphere", "--width", &w, "--height", &h, "--out", name];
    args.extend_from_slice(extra);
    run_ok(dir, &args);
    read_pfm(&dir.join(name)).unwrap()
}

#[test]
fn golden_render_is_reproduced_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let image = render(dir.path(), "g.pfm", &["--spp", "64", "--seed", "0"]);
    if std::env::var_os("PICOMIS_BLESS").is_some() {
        std::fs::copy(dir.path().join("g.pfm"), golden_path()).unwrap();
        eprintln!("wrote {}", golden_path().display());
    }
    let golden = read_pfm(&golden_path()).expect("golden image (PICOMIS_BLESS=1 creates it)");
    assert_eq!((image.width, image.height), (golden.width, golden.height));
    let differing: Vec<(usize, f32)> = image
        .data
        .iter()
        .zip(&golden.data)
        .enumerate()
        .filter(|(_, (a, b))| a.to_array().map(f32::to_bits) != b.to_array().map(f32::to_bits))
        .map(|(i, (a, b))| (i, (*a - *b).abs().max_element()))
        .collect();
    assert!(
        differing.is_empty(),
        "{} of {} pixels differ from the golden (largest difference {:?})",
        differing.len(),
        image.data.len(),
        differing.iter().map(|d| d.1).fold(0.0f32, f32::max)
    );
}

/// The scene's parameters, read from its file so the test follows the scene.
struct LambertScene {
    origin: [f64; 3],
    target: [f64; 3],
    fov_y_deg: f64,
    center: [f64; 3],
    radius: f64,
    radiance: f64,
    albedo: f64,
    half_size: f64,
}

fn scene() -> LambertScene {
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/lambert_sphere.json"))
            .unwrap();
    let j: serde_json::Value = serde_json::from_str(&text).unwrap();
    let v3 = |v: &serde_json::Value| [0, 1, 2].map(|i| v[i].as_f64().unwrap());
    let cam = &j["camera"];
    assert_eq!(cam["up"], serde_json::json!([0.0, 1.0, 0.0]));
    assert_eq!(cam["fov_axis"], "y");
    let plane = &j["shapes"][0];
    let light = &j["shapes"][1];
    assert_eq!(plane["normal"], serde_json::json!([0.0, 1.0, 0.0]));
    assert_eq!(plane["p0"][1].as_f64(), Some(0.0), "the plane is y = 0");
    let half_size = plane["p1"][0].as_f64().unwrap();
    let albedo = j["materials"][plane["material"].as_str().unwrap()]["albedo"][0].as_f64().unwrap();
    let s = LambertScene {
        origin: v3(&cam["origin"]),
        target: v3(&cam["target"]),
        fov_y_deg: cam["fov_deg"].as_f64().unwrap(),
        center: v3(&light["center"]),
        radius: light["radius"].as_f64().unwrap(),
        radiance: light["emitter"]["radiance"][0].as_f64().unwrap(),
        albedo,
        half_size,
    };
    // The closed form needs the sphere fully above every plane point's horizon.
    assert!(s.center[1] >= s.radius);
    s
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
fn normalize(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

/// Expected pixel values: the closed form averaged over a 16x16 grid in each pixel (the box
/// filter), `None` for pixels whose footprint is not entirely plane.
fn expected(s: &LambertScene) -> Vec<Option<f64>> {
    let forward = normalize(sub(s.target, s.origin));
    let right = normalize(cross(forward, [0.0, 1.0, 0.0]));
    let up = cross(right, forward);
    let tan_y = (s.fov_y_deg.to_radians() / 2.0).tan();
    let tan_x = tan_y * f64::from(W) / f64::from(H);
    const N: u32 = 16;
    let mut out = Vec::new();
    for py in 0..H {
        for px in 0..W {
            let mut sum = 0.0;
            let mut pure = true;
            for sy in 0..N {
                for sx in 0..N {
                    let u = (f64::from(px) + (f64::from(sx) + 0.5) / f64::from(N)) / f64::from(W);
                    let v = (f64::from(py) + (f64::from(sy) + 0.5) / f64::from(N)) / f64::from(H);
                    let (a, b) = ((2.0 * u - 1.0) * tan_x, (1.0 - 2.0 * v) * tan_y);
                    let dir = normalize([0, 1, 2].map(|i| forward[i] + a * right[i] + b * up[i]));
                    // Does the ray meet the sphere?
                    let oc = sub(s.origin, s.center);
                    let (bq, cq) = (dot(oc, dir), dot(oc, oc) - s.radius * s.radius);
                    let hits_sphere = bq * bq - cq > 0.0 && -bq - (bq * bq - cq).sqrt() > 0.0;
                    let t = -s.origin[1] / dir[1];
                    let x = [0, 1, 2].map(|i| s.origin[i] + t * dir[i]);
                    let on_plane = dir[1] < 0.0 && x[0].abs() <= s.half_size && x[2].abs() <= s.half_size;
                    if hits_sphere || !on_plane {
                        pure = false;
                        continue;
                    }
                    let d = dot(sub(s.center, x), sub(s.center, x)).sqrt();
                    sum += s.albedo * s.radiance * s.radius * s.radius * s.center[1] / (d * d * d);
                }
            }
            out.push(pure.then(|| sum / f64::from(N * N)));
        }
    }
    out
}

/// Per-pixel mean and variance of the mean of `k` renders with seeds 1..=k.
fn renders(dir: &Path, mis: &str, k: u32, spp: u32) -> (Vec<f64>, Vec<f64>) {
    let images: Vec<Image> = (1..=k)
        .map(|seed| {
            let (seed, spp) = (seed.to_string(), spp.to_string());
            render(dir, &format!("{mis}{seed}.pfm"), &["--mis", mis, "--seed", &seed, "--spp", &spp])
        })
        .collect();
    let n = (W * H) as usize;
    let (mut mean, mut var) = (vec![0.0; n], vec![0.0; n]);
    for p in 0..n {
        // The scene is grey: use the green channel.
        let v: Vec<f64> = images.iter().map(|im| f64::from(im.data[p].y)).collect();
        let m = v.iter().sum::<f64>() / f64::from(k);
        mean[p] = m;
        var[p] = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / f64::from(k - 1) / f64::from(k);
    }
    (mean, var)
}

/// z-scores of `mean` against `expected` per 4x4 block (pixels are independent, so a block's
/// variance is the sum of its pixels'), and over the whole image.
fn z_scores(mean: &[f64], var: &[f64], expected: &[Option<f64>]) -> (Vec<f64>, f64, f64) {
    let mut blocks = Vec::new();
    let (mut diff, mut total_var, mut total_ref) = (0.0, 0.0, 0.0);
    for by in 0..H / 4 {
        for bx in 0..W / 4 {
            let (mut d, mut v, mut n) = (0.0, 0.0, 0);
            for y in by * 4..by * 4 + 4 {
                for x in bx * 4..bx * 4 + 4 {
                    let p = (y * W + x) as usize;
                    if let Some(e) = expected[p] {
                        d += mean[p] - e;
                        v += var[p];
                        n += 1;
                        total_ref += e;
                    }
                }
            }
            if n >= 8 {
                blocks.push(d / v.sqrt());
            }
            diff += d;
            total_var += v;
        }
    }
    (blocks, diff / total_var.sqrt(), diff / total_ref)
}

#[test]
fn lambert_sphere_matches_the_closed_form() {
    let s = scene();
    let expected = expected(&s);
    let plane_pixels = expected.iter().filter(|e| e.is_some()).count();
    assert!(plane_pixels > 500, "only {plane_pixels} pixels see only the plane");
    let dir = tempfile::tempdir().unwrap();
    // Each technique alone and combined converges to the closed form. 8 independent renders of
    // 32 spp give each pixel's variance; z-scores over 4x4 blocks and the whole image.
    // Not vacuous: each run must also reject the same images off by `detect` (BSDF sampling
    // alone is ~20x noisier here, a small light seen from a diffuse plane, so 10 % for it).
    for (mis, detect) in [("power", 0.02), ("balance", 0.02), ("light", 0.02), ("bsdf", 0.10)] {
        let (mean, var) = renders(dir.path(), mis, 8, 32);
        let (blocks, z_all, rel) = z_scores(&mean, &var, &expected);
        let max_z = blocks.iter().fold(0.0f64, |m, z| m.max(z.abs()));
        eprintln!(
            "{mis}: {} blocks, max |z| {max_z:.2}, image z {z_all:+.2}, relative error {rel:+.5}",
            blocks.len()
        );
        assert!(blocks.len() >= 30);
        // 48 blocks of Gaussian z: P(any |z| > 4.5) ~ 3e-4; the whole image within 4 sigma.
        assert!(max_z < 4.5 && z_all.abs() < 4.0, "{mis} disagrees with the closed form: {blocks:?}");
        let off: Vec<f64> = mean.iter().map(|m| m * (1.0 + detect)).collect();
        assert!(z_scores(&off, &var, &expected).1.abs() > 4.0, "{mis}: the test cannot see a {detect} error");
    }

    // The golden itself (seed 0, 64 spp) against the closed form, with the variance of a 32-spp
    // render halved.
    let golden = read_pfm(&golden_path()).unwrap();
    let (_, var) = renders(dir.path(), "power", 8, 32);
    let var_golden: Vec<f64> = var.iter().map(|v| v * 8.0 / 2.0).collect();
    let mean: Vec<f64> = golden.data.iter().map(|c| f64::from(c.y)).collect();
    let (_, z_all, rel) = z_scores(&mean, &var_golden, &expected);
    eprintln!("golden: image z {z_all:+.2}, relative error {rel:+.5}");
    assert!(z_all.abs() < 4.0, "the golden disagrees with the closed form (z {z_all})");
}
