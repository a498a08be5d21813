//! Beyond the lecture, measured at equal spp (issue 14): the relative MSE of the reflected (direct)
//! light against a converged reference, on every built-in scene or the scene files named.
//!
//! - `quads`: quad lights by area, in solid angle, and in solid angle warped by the receiver's
//!   cosine, each with the balance and power heuristics and light sampling alone (the kernel's
//!   estimator for the settings, `picomis_host::renderer`; scenes without a rectangular quad
//!   light are skipped).
//! - `weights`: the balance and power heuristics against variance-aware weights (Grittmann,
//!   Georgiev, Slusallek and Křivánek 2019): balance on c_l n_l p_l and c_b n_b p_b with a
//!   per-pixel factor c_i of each technique from a pilot pass, 1/V_i or 1 + mu_i^2/V_i, V_i
//!   estimated (a) from the pilot samples of the pixel, (b) across the pixel means of 8 x 8 pixel
//!   blocks (the authors' implementation), (c) across the pixel means of independent pilot
//!   renders (the variance of the stratified pixel estimate itself: an oracle). Every weighting
//!   is applied to the same samples (a host-side copy of the kernel's multi-sample estimator with
//!   the scene's light selection and sphere sampling, quads by area, no lobe mixing, checked bit
//!   for bit against the kernel's `camera_sample` under the balance heuristic), so the ratios are
//!   paired; the pilot is not counted.
//!
//! The reference is the kernel's balance heuristic at `--ref-spp` in two independent halves
//! (their difference gives its own noise, subtracted from every figure), cached in the system's
//! temporary folder. Films are scaled down to at most 128 x 96 pixels' worth.
//!
//! The README's figures (each also with `--sampler independent`; the scenes with quad lights are
//! two built-in ones and two of `tests/scenes/`):
//!
//! ```sh
//! cargo run --release -p picomis-bench --example beyond -- quads box_quad stress \
//!   tests/scenes/panel_room.json tests/scenes/low_ceiling.json --spp 64 --seeds 4
//! cargo run --release -p picomis-bench --example beyond -- weights --spp 64 --seeds 4 --pilots 16
//! ```
//!
//! Options: `--spp N` (64), `--seeds K` (4), `--ref-spp N` (8192), `--pilot-spp N` (`--spp`),
//! `--pilots K` (8), `--sampler sobol|independent` (sobol).

use std::path::PathBuf;

use picomis::light::select::{ByContribution, ByPower, Select, Uniform};
use picomis::light::sphere::{self, SphereSampler};
use picomis::light::{lobe, quad};
use picomis::num::Frame;
use picomis::{
    ControlVariate, Estimate, Film, Heuristic, Hit, LightSampler, LightSelection, Lights, LobeMixing, Method,
    MisModel, Preset, QuadSampling, Ray, RenderSettings, Rgb, Sampler, SamplerKind, ShadingPoint,
    SphereSampling, Technique, Vec2, Vec3,
};
use picomis_bench::{HOST_LIGHTS, HOST_MATERIALS, HOST_SHAPES, HostScene, builtin_scenes};
use picomis_format::SceneFile;
use rayon::prelude::*;

/// The command line.
#[derive(Clone, Debug)]
struct Args {
    mode: String,
    files: Vec<SceneFile>,
    spp: u32,
    seeds: u32,
    ref_spp: u32,
    pilot_spp: u32,
    pilots: u32,
    sampler: SamplerKind,
}

fn parse_args() -> Args {
    let mut it = std::env::args().skip(1);
    let mode = it.next().unwrap_or_default();
    assert!(mode == "quads" || mode == "weights", "usage: beyond quads|weights [SCENE...] [--spp N] ...");
    let mut args = Args {
        mode,
        files: Vec::new(),
        spp: 64,
        seeds: 4,
        ref_spp: 8192,
        pilot_spp: 0,
        pilots: 8,
        sampler: Preset::Best.settings().sampler(),
    };
    let mut names = Vec::new();
    while let Some(a) = it.next() {
        let mut value = || it.next().unwrap_or_else(|| panic!("{a} needs a value"));
        match a.as_str() {
            "--spp" => args.spp = value().parse().expect("--spp N"),
            "--seeds" => args.seeds = value().parse().expect("--seeds K"),
            "--ref-spp" => args.ref_spp = value().parse().expect("--ref-spp N"),
            "--pilot-spp" => args.pilot_spp = value().parse().expect("--pilot-spp N"),
            "--pilots" => args.pilots = value().parse().expect("--pilots K"),
            "--sampler" => args.sampler = SamplerKind::from_name(&value()).expect("sobol or independent"),
            _ => names.push(a),
        }
    }
    if args.pilot_spp == 0 {
        args.pilot_spp = args.spp;
    }
    let builtins = builtin_scenes();
    args.files = if names.is_empty() {
        builtins
    } else {
        let load = |n: &String| match builtins.iter().find(|f| f.name() == n) {
            Some(f) => f.clone(),
            None => SceneFile::load(&PathBuf::from(n)).unwrap_or_else(|e| panic!("{e}")),
        };
        names.iter().map(load).collect()
    };
    args
}

/// The scene's film scaled down to at most 128 x 96 pixels' worth.
fn study_film(file: &SceneFile) -> Film {
    let f = file.film();
    let scale = (128.0 * 96.0 / f64::from(f.pixels())).sqrt().min(1.0);
    let side = |v: u32| ((f64::from(v) * scale).round() as u32).max(1);
    Film::new(side(f.width()), side(f.height())).expect("a valid film")
}

/// Mean of (I - R)^2 / (R^2 + 0.01) over pixels and channels (MIS-NOTES section 6).
fn rel_mse(image: &[[f64; 3]], reference: &[[f64; 3]]) -> f64 {
    let mut sum = 0.0;
    for (i, r) in image.iter().zip(reference) {
        for c in 0..3 {
            sum += (i[c] - r[c]).powi(2) / (r[c] * r[c] + 0.01);
        }
    }
    sum / (3 * image.len()) as f64
}

fn rgb64(c: Rgb) -> [f64; 3] {
    [f64::from(c.x), f64::from(c.y), f64::from(c.z)]
}

/// The reflected light of every pixel at `settings` (the kernel), in parallel over rows.
fn render_reflected(scene: &HostScene, settings: &RenderSettings) -> Vec<[f64; 3]> {
    let renderer = picomis_host::renderer(scene, settings).expect("settings the kernel accepts");
    let renderer = &*renderer;
    let film = scene.film();
    (0..film.height())
        .into_par_iter()
        .flat_map_iter(|y| {
            (0..film.width()).map(move |x| {
                let mut sum = [0.0; 3];
                for s in 0..settings.spp() {
                    let e = renderer.camera_sample(x, y, s);
                    let r = rgb64(e.light.contribution + e.bsdf.contribution);
                    (0..3).for_each(|c| sum[c] += r[c]);
                }
                sum.map(|v| v / f64::from(settings.spp()))
            })
        })
        .collect()
}

/// The reference (balance, quads in solid angle, the default stream) and its own relative MSE.
fn reference(name: &str, scene: &HostScene, spp: u32) -> (Vec<[f64; 3]>, f64) {
    let film = scene.film();
    let dir = std::env::temp_dir().join("picomis-beyond");
    let _ = std::fs::create_dir_all(&dir);
    let half = |k: u32| {
        let path = dir.join(format!("{name}-{}x{}-{spp}-{k}.bin", film.width(), film.height()));
        if let Ok(bytes) = std::fs::read(&path) {
            if bytes.len() == film.pixels() as usize * 24 {
                let v: Vec<f64> = bytes
                    .chunks_exact(8)
                    .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
                    .collect();
                return v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect::<Vec<_>>();
            }
        }
        let settings = RenderSettings::new(Method::Mis(Heuristic::Balance), 1, 1, spp / 2, 0x5EED_0000 + k)
            .expect("valid settings")
            .with_quad_sampling(QuadSampling::SolidAngle);
        let image = render_reflected(scene, &settings);
        let bytes: Vec<u8> = image.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
        let _ = std::fs::write(&path, bytes);
        image
    };
    let (a, b) = (half(0), half(1));
    let r: Vec<[f64; 3]> = a.iter().zip(&b).map(|(a, b)| [0, 1, 2].map(|c| 0.5 * (a[c] + b[c]))).collect();
    // Var[(A + B) / 2] = E[(A - B)^2] / 4.
    let noise = rel_mse(&a, &b) / 4.0;
    (r, noise)
}

fn has_rectangle_light(scene: &HostScene) -> bool {
    scene.lights().iter().any(|l| scene.light_shape(l).and_then(|s| s.as_rectangle()).is_some())
}

// ---------------------------------------------------------------------------------------------
// quads

/// `file` built as the host's scene for [`study_film`].
fn build(file: &SceneFile) -> HostScene {
    file.build_with_film::<HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS>(study_film(file))
        .unwrap_or_else(|e| panic!("{e}"))
}

fn quads(file: &SceneFile, args: &Args) {
    let scene = build(file);
    if !has_rectangle_light(&scene) {
        println!("{}: no rectangular quad light, skipped", file.name());
        return;
    }
    let (r, noise) = reference(file.name(), &scene, args.ref_spp);
    let base = file.default_settings().with_sampler(args.sampler);
    println!(
        "{} ({}x{}, {} spp, {} seeds, {}; reference noise {noise:.2e} subtracted)",
        file.name(),
        scene.film().width(),
        scene.film().height(),
        args.spp,
        args.seeds,
        args.sampler.name()
    );
    println!("| method | area | solid-angle | solid-angle-cosine | solid angle / cosine |");
    println!("|---|---:|---:|---:|---:|");
    for name in ["balance", "power", "light"] {
        let method = Method::from_name(name).expect("a kernel method");
        let errors: Vec<f64> = QuadSampling::ALL
            .iter()
            .map(|&q| {
                let mut sum = 0.0;
                for seed in 0..args.seeds {
                    let s = RenderSettings::new(method, 1, 1, args.spp, 1 + seed)
                        .expect("valid settings")
                        .with_sampler(base.sampler())
                        .with_light_selection(base.light_selection())
                        .with_sphere_sampling(base.sphere_sampling())
                        .with_quad_sampling(q);
                    sum += rel_mse(&render_reflected(&scene, &s), &r) - noise;
                }
                sum / f64::from(args.seeds)
            })
            .collect();
        println!(
            "| {name} | {:.3e} | {:.3e} | {:.3e} | {:.2} |",
            errors[0],
            errors[1],
            errors[2],
            errors[1] / errors[2]
        );
    }
}

// ---------------------------------------------------------------------------------------------
// weights: a host-side copy of the kernel's multi-sample estimator (one light and one BSDF
// sample, no control variate) that keeps each sample's value and pdfs

/// What one camera sample found: each technique's sample as (f L, p_l, p_b); the light sample's
/// value is not divided by any pdf, the BSDF sample's is divided by p_b (as in the kernel).
#[derive(Clone, Copy, Debug, Default)]
struct Found {
    light: Option<(Rgb, f32, f32)>,
    /// A delta light's sample (weight one): f L and P(light).
    delta: Option<(Rgb, f32)>,
    bsdf: Option<(Rgb, f32, f32)>,
}

/// The light sampler of the copy of the estimator: the strategies `Lt` in the host's scene.
type Copy<'a, Lt> = LightSampler<'a, Lt, HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS>;

/// The light strategies of the copy: light selection `Sel`, spheres by `Sp`, quads by area, no
/// lobe mixing.
type CopyLights<Sel, Sp> = Lights<Sel, Sp, quad::ByArea, lobe::Off>;

fn camera_found<Sel: Select<HOST_LIGHTS>, Sp: SphereSampler>(
    lights: &Copy<'_, CopyLights<Sel, Sp>>,
    settings: &RenderSettings,
    x: u32,
    y: u32,
    index: u32,
) -> Found {
    let scene = lights.scene();
    let film = scene.film();
    let mut sampler = Sampler::with_kind(settings.sampler(), settings.seed(), y * film.width() + x, index);
    let jitter = sampler.next_2d();
    let uv =
        Vec2::new((x as f32 + jitter.x) / film.width() as f32, (y as f32 + jitter.y) / film.height() as f32);
    let (ray, t_near) = scene.camera().ray(uv);
    match scene.intersect(&ray, t_near, f32::INFINITY, None) {
        Some(hit) if hit.front => direct_found(lights, &hit, -ray.dir, &mut sampler),
        _ => Found::default(),
    }
}

fn direct_found<Sel: Select<HOST_LIGHTS>, Sp: SphereSampler>(
    lights: &Copy<'_, CopyLights<Sel, Sp>>,
    x: &Hit,
    wo_world: Vec3,
    sampler: &mut Sampler,
) -> Found {
    let scene = lights.scene();
    let mut found = Found::default();
    let Some(bsdf) = scene.material(x.object).filter(|m| !m.is_black()) else { return found };
    let frame = Frame::from_normal(x.point.n);
    let at = ShadingPoint { p: x.point.p, n: x.point.n, wo: wo_world, bsdf: *bsdf };
    let wo = frame.to_local(wo_world);
    let selection = lights.selection_at(&at);
    // The light sample: one 2-D request chooses the light and, rescaled, places the point.
    let (u_select, v) = sampler.next_2d_reusable();
    if let Some((chosen, ls)) = lights
        .select_reusing(&selection, u_select)
        .and_then(|(c, u)| Some((c, lights.sample(c.light, &at, Vec2::new(u, v))?)))
    {
        let p_light = chosen.probability * ls.pdf;
        let (f, p_bsdf) = bsdf.eval_pdf(wo, frame.to_local(ls.wi));
        let shadow = Ray { origin: at.p, dir: ls.wi };
        if f != Rgb::ZERO
            && ls.radiance != Rgb::ZERO
            && scene.unoccluded(&shadow, ls.distance, x.object, ls.emitter)
        {
            if ls.delta {
                found.delta = Some((f * ls.radiance, p_light));
            } else {
                found.light = Some((f * ls.radiance, p_light, p_bsdf));
            }
        }
    }
    // The BSDF sample.
    if let Some(bs) = bsdf.sample(wo, sampler.next_2d()) {
        let ray = Ray { origin: at.p, dir: frame.to_world(bs.wi) };
        if let Some((y, light, radiance)) = scene.emitter_hit(&ray, x.object) {
            if radiance != Rgb::ZERO {
                let p_light = lights.pmf(&selection, light) * lights.pdf(light, &at, &y.point);
                found.bsdf = Some((bs.weight * radiance, bsdf.pdf(wo, bs.wi), p_light));
            }
        }
    }
    found
}

/// The kernel's bound on one sample's contribution.
fn bounded(c: Rgb) -> Rgb {
    let ok = |v: f32| v.abs() <= picomis::MAX_CONTRIBUTION;
    if ok(c.x) && ok(c.y) && ok(c.z) { c } else { Rgb::ZERO }
}

/// The reflected light of a camera sample with the weights of `heuristic`, the light technique's
/// q scaled by `c_light` (1: the heuristic itself), in f32 as the kernel computes it.
fn weighted(f: &Found, heuristic: Heuristic, c_light: f32) -> Rgb {
    let m = Method::Mis(heuristic);
    let mut sum = Rgb::ZERO;
    if let Some((value, p_l)) = f.delta {
        sum += bounded(value * (1.0 / p_l));
    }
    if let Some((value, p_l, p_b)) = f.light {
        let w = m.weight(Technique::Light, c_light * p_l, p_b);
        sum += bounded(value * (w / p_l));
    }
    if let Some((value, p_b, p_l)) = f.bsdf {
        let w = m.weight(Technique::Bsdf, c_light * p_l, p_b);
        sum += bounded(value * w);
    }
    sum
}

/// The unweighted estimates of each technique alone (area lights only): f L / p_l and f L / p_b.
fn unweighted(f: &Found) -> (f64, f64) {
    let lum = |c: Rgb| f64::from(picomis::num::luminance(c));
    (f.light.map_or(0.0, |(v, p, _)| lum(v) / f64::from(p)), f.bsdf.map_or(0.0, |(v, ..)| lum(v)))
}

/// Running mean and variance.
#[derive(Clone, Copy, Debug, Default)]
struct Moments {
    n: f64,
    mean: f64,
    m2: f64,
}

impl Moments {
    fn push(&mut self, x: f64) {
        self.n += 1.0;
        let d = x - self.mean;
        self.mean += d / self.n;
        self.m2 += d * (x - self.mean);
    }
    fn variance(&self) -> f64 {
        if self.n > 1.0 { self.m2 / (self.n - 1.0) } else { 0.0 }
    }
}

/// Per pixel and technique (light, BSDF): the variance of a pilot sample, and the pixel means of
/// each pilot render.
struct Pilot {
    per_sample: Vec<[Moments; 2]>,
    per_render: Vec<[Moments; 2]>,
    /// The pixel means of the first pilot render.
    first: Vec<[f64; 2]>,
}

fn pilot<Sel: Select<HOST_LIGHTS>, Sp: SphereSampler>(
    lights: &Copy<'_, CopyLights<Sel, Sp>>,
    settings: &RenderSettings,
    pilots: u32,
) -> Pilot {
    let film = lights.scene().film();
    let per_pixel: Vec<([Moments; 2], [Moments; 2], [f64; 2])> = (0..film.pixels())
        .into_par_iter()
        .map(|i| {
            let (x, y) = (i % film.width(), i / film.width());
            let (mut per_sample, mut per_render, mut first) =
                ([Moments::default(); 2], [Moments::default(); 2], [0.0; 2]);
            for k in 0..pilots {
                let s = settings.with_seed(0x9170_0000 + k);
                let mut mean = [0.0; 2];
                for index in 0..s.spp() {
                    let (l, b) = unweighted(&camera_found(lights, &s, x, y, index));
                    if k == 0 {
                        per_sample[0].push(l);
                        per_sample[1].push(b);
                    }
                    mean[0] += l / f64::from(s.spp());
                    mean[1] += b / f64::from(s.spp());
                }
                per_render[0].push(mean[0]);
                per_render[1].push(mean[1]);
                if k == 0 {
                    first = mean;
                }
            }
            (per_sample, per_render, first)
        })
        .collect();
    Pilot {
        per_sample: per_pixel.iter().map(|p| p.0).collect(),
        per_render: per_pixel.iter().map(|p| p.1).collect(),
        first: per_pixel.iter().map(|p| p.2).collect(),
    }
}

/// The block variance of the first pilot's pixel means (8 x 8 blocks).
fn block_moments(pilot: &Pilot, film: Film) -> Vec<[Moments; 2]> {
    const B: u32 = 8;
    let (w, h) = (film.width(), film.height());
    let mut blocks = vec![[Moments::default(); 2]; (w.div_ceil(B) * h.div_ceil(B)) as usize];
    for y in 0..h {
        for x in 0..w {
            let b = &mut blocks[((y / B) * w.div_ceil(B) + x / B) as usize];
            let m = pilot.first[(y * w + x) as usize];
            b[0].push(m[0]);
            b[1].push(m[1]);
        }
    }
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| blocks[((y / B) * w.div_ceil(B) + x / B) as usize])
        .collect()
}

/// The light technique's factor relative to the BSDF technique's, c_l / c_b, from the two
/// techniques' moments: 1 / V (`second_moment` false) or 1 + mu^2 / V; 1 where either is
/// unknown, clamped to [1e-4, 1e4].
fn factor(m: &[Moments; 2], second_moment: bool) -> f32 {
    let c = |m: &Moments| {
        let v = m.variance();
        (v > 0.0).then(|| if second_moment { 1.0 + m.mean * m.mean / v } else { 1.0 / v })
    };
    match (c(&m[0]), c(&m[1])) {
        (Some(l), Some(b)) => (l / b).clamp(1e-4, 1e4) as f32,
        // Light sampling exact (zero variance) and BSDF sampling not: all weight to light.
        (None, Some(_)) if m[0].n > 1.0 && m[0].mean > 0.0 => 1e4,
        (Some(_), None) if m[1].n > 1.0 && m[1].mean > 0.0 => 1e-4,
        _ => 1.0,
    }
}

/// The weights study with the scene's light selection and sphere sampling, as the types the copy
/// of the estimator is built for.
fn weights(file: &SceneFile, args: &Args) {
    let base = file.default_settings();
    match (base.light_selection(), base.sphere_sampling()) {
        (LightSelection::Uniform, SphereSampling::Area) => {
            weights_with::<Uniform, sphere::ByArea>(file, args)
        }
        (LightSelection::Uniform, SphereSampling::Cone) => {
            weights_with::<Uniform, sphere::InCone>(file, args)
        }
        (LightSelection::Power, SphereSampling::Area) => {
            weights_with::<ByPower<HOST_LIGHTS>, sphere::ByArea>(file, args)
        }
        (LightSelection::Power, SphereSampling::Cone) => {
            weights_with::<ByPower<HOST_LIGHTS>, sphere::InCone>(file, args)
        }
        (LightSelection::Contribution, SphereSampling::Area) => {
            weights_with::<ByContribution<HOST_LIGHTS>, sphere::ByArea>(file, args)
        }
        (LightSelection::Contribution, SphereSampling::Cone) => {
            weights_with::<ByContribution<HOST_LIGHTS>, sphere::InCone>(file, args)
        }
        (LightSelection::Every, _) => {
            eprintln!("beyond: the weights study draws one light per light sample, not `every`");
            std::process::exit(2);
        }
    }
}

fn weights_with<Sel: Select<HOST_LIGHTS>, Sp: SphereSampler>(file: &SceneFile, args: &Args) {
    let scene = build(file);
    let film = scene.film();
    let (r, noise) = reference(file.name(), &scene, args.ref_spp);
    // The strategies of the copy of the estimator, named in full.
    let settings = RenderSettings::new(Method::Mis(Heuristic::Balance), 1, 1, args.spp, 1)
        .and_then(|s| s.with_mis_model(MisModel::Multi))
        .and_then(|s| s.with_control_variate(ControlVariate::Off))
        .expect("valid settings")
        .with_sampler(args.sampler)
        .with_light_selection(Sel::KIND)
        .with_sphere_sampling(Sp::KIND)
        .with_quad_sampling(QuadSampling::Area)
        .with_lobe_mixing(LobeMixing::Off);
    let lights = Copy::<CopyLights<Sel, Sp>>::new(&scene);
    let kernel = picomis_host::renderer(&scene, &settings).expect("settings the kernel accepts");

    // The copy of the estimator gives the kernel's bits under the balance heuristic.
    for (x, y, s) in
        [(film.width() / 2, film.height() / 2, 0), (3, film.height() - 2, 5), (film.width() / 3, 1, 2)]
    {
        let e: Estimate = kernel.camera_sample(x, y, s);
        let mine = weighted(&camera_found(&lights, &settings, x, y, s), Heuristic::Balance, 1.0);
        assert_eq!(mine, e.light.contribution + e.bsdf.contribution, "{}: pixel ({x}, {y})", file.name());
    }

    let pilot_settings = settings.with_spp(args.pilot_spp).expect("spp > 0");
    let p = pilot(&lights, &pilot_settings, args.pilots);
    let blocks = block_moments(&p, film);
    let power = Heuristic::Power { beta: 2.0 };
    let schemes: Vec<(&str, Heuristic, Vec<f32>)> = vec![
        ("balance", Heuristic::Balance, vec![1.0; film.pixels() as usize]),
        ("power", power, vec![1.0; film.pixels() as usize]),
        (
            "VA 1/V, pilot samples",
            Heuristic::Balance,
            p.per_sample.iter().map(|m| factor(m, false)).collect(),
        ),
        (
            "VA 1+mu^2/V, pilot samples",
            Heuristic::Balance,
            p.per_sample.iter().map(|m| factor(m, true)).collect(),
        ),
        ("VA 1/V, 8x8 blocks", Heuristic::Balance, blocks.iter().map(|m| factor(m, false)).collect()),
        ("VA 1+mu^2/V, 8x8 blocks", Heuristic::Balance, blocks.iter().map(|m| factor(m, true)).collect()),
        ("VA 1/V, oracle", Heuristic::Balance, p.per_render.iter().map(|m| factor(m, false)).collect()),
        ("VA 1+mu^2/V, oracle", Heuristic::Balance, p.per_render.iter().map(|m| factor(m, true)).collect()),
        ("power on VA 1+mu^2/V, 8x8 blocks", power, blocks.iter().map(|m| factor(m, true)).collect()),
        ("power on VA 1/V, oracle", power, p.per_render.iter().map(|m| factor(m, false)).collect()),
    ];
    let mut errors = vec![0.0; schemes.len()];
    for seed in 0..args.seeds {
        let s = settings.with_seed(1 + seed);
        let images: Vec<Vec<[f64; 3]>> = (0..film.pixels())
            .into_par_iter()
            .map(|i| {
                let (x, y) = (i % film.width(), i / film.width());
                let mut sums = vec![[0.0; 3]; schemes.len()];
                for index in 0..s.spp() {
                    let f = camera_found(&lights, &s, x, y, index);
                    for (k, (_, h, c)) in schemes.iter().enumerate() {
                        let v = rgb64(weighted(&f, *h, c[i as usize]));
                        (0..3).for_each(|ch| sums[k][ch] += v[ch] / f64::from(s.spp()));
                    }
                }
                sums
            })
            .collect();
        for (k, e) in errors.iter_mut().enumerate() {
            let image: Vec<[f64; 3]> = images.iter().map(|px| px[k]).collect();
            *e += (rel_mse(&image, &r) - noise) / f64::from(args.seeds);
        }
    }
    println!(
        "{} ({}x{}, {} spp, {} seeds, {}; pilot {} spp x {} renders; reference noise {noise:.2e} subtracted)",
        file.name(),
        film.width(),
        film.height(),
        args.spp,
        args.seeds,
        args.sampler.name(),
        args.pilot_spp,
        args.pilots
    );
    println!("| weights | relative MSE | balance / this |");
    println!("|---|---:|---:|");
    for ((name, ..), e) in schemes.iter().zip(&errors) {
        println!("| {name} | {e:.3e} | {:.2} |", errors[0] / e);
    }
}

fn main() {
    let args = parse_args();
    for file in &args.files {
        match args.mode.as_str() {
            "quads" => quads(file, &args),
            _ => weights(file, &args),
        }
    }
}
