//! Lobe mixing's constants, measured: `LOBE_SHARE` (the lobe's share of the light samples where it
//! applies) and `LOBE_NARROWER` (it applies where the GGX alpha is below this fraction of the
//! sine of the light's angular radius), in `kernel/src/light/lobe.rs`, by the error they give at
//! equal spp. Deterministic (fixed seeds, no timing).
//!
//! Each candidate pair is run through a host-side copy of the kernel's multi-sample estimator
//! whose light technique is lobe mixing's mixture with the candidate constants: the light's own
//! part from the kernel's light sampler without lobe mixing, the lobe's part from a copy of
//! `Lobe::towards` with the candidate `LOBE_NARROWER` (the kernel's slope boxes and GGX sampling
//! routines, `picomis::sampling`). At the kernel's constants the copy gives the kernel's camera
//! samples bit for bit (asserted on every scene before measuring). The strategies are the `best`
//! preset's (lights by contribution, spheres by cone, quads by area, the power heuristic, one
//! light and one BSDF sample) without the control variate, which acts on Lambertian receivers
//! only, where lobe mixing does not: every candidate renders the Lambertian pixels alike.
//!
//! For each scene (default: the glossy ones, `veach_mis`, `stress` and
//! `tests/scenes/mirror_lights.json`, and `tests/scenes/glossy_lights.json`, where the lobes are
//! wider than the lights and nothing may change) it prints the relative MSE of the reflected light
//! at `--spp` (64) over `--seeds` (4) sobol renders against a reference of `--ref-spp` (8192; the
//! kernel's balance heuristic in two independent halves, whose noise is subtracted, cached in the
//! system's temporary folder like the `beyond` example's), for every pair of a share in {1/4, 1/2,
//! 3/4, 7/8} and a bound in {1/4, 1/2, 1, 2, every GGX receiver}, and without lobe mixing; then
//! each pair's error relative to the kernel's pair, averaged over the scenes (geometric mean).
//! The same seeds for every candidate: the differences are paired.
//!
//! ```sh
//! cargo run --release -p picomis-bench --example lobe_constants
//! ```
//!
//! Films are scaled down to at most 128 x 96 pixels' worth. Options: `--spp N`, `--seeds K`,
//! `--ref-spp N`, scene names or files.

// `!(x > 0.0)` on purpose, as in the kernel: unlike `x <= 0.0` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::path::PathBuf;

use picomis::light::lobe::{LOBE_INSIDE, LOBE_NARROWER, LOBE_REACH, LOBE_SHARE};
use picomis::light::select::ByContribution;
use picomis::light::{lobe, quad, sphere};
use picomis::num::{Frame, dot, sqrt};
use picomis::sampling::{
    SlopeBox, cone_one_minus_cos, ggx_reflection_in_pdf, nearest_edge, sample_ggx_reflection_in,
};
use picomis::{
    ControlVariate, Film, Heuristic, Hit, Light, LightId, LightSample, LightSampler, LightSelection, Lights,
    LobeMixing, Material, Method, Preset, QuadSampling, Ray, RenderSettings, Rgb, Sampler, ShadingPoint,
    Shape, SphereSampling, SurfacePoint, Technique, Vec2, Vec3,
};
use picomis_bench::{HOST_LIGHTS, HOST_MATERIALS, HOST_SHAPES, HostScene, builtin_scenes};
use picomis_format::SceneFile;
use rayon::prelude::*;

/// The light strategies of the copy's own part: the best preset's, without lobe mixing.
type Own = Lights<ByContribution<HOST_LIGHTS>, sphere::InCone, quad::ByArea, lobe::Off>;

/// The light sampler of the light's own part.
type OwnSampler<'a> = LightSampler<'a, Own, HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS>;

/// How far outside a light's bounding sphere a receiver must be for its lobe to apply (the
/// kernel's private `CLEAR`).
const CLEAR: f32 = 1.001;

/// A candidate pair of constants; `None`: no lobe mixing.
type Candidate = Option<(f32, f32)>;

/// The kernel's pair.
const KERNEL: (f32, f32) = (LOBE_SHARE, LOBE_NARROWER);

/// The shares and bounds tried.
const SHARES: [f32; 4] = [0.25, 0.5, 0.75, 0.875];
const NARROWER: [f32; 5] = [0.25, 0.5, 1.0, 2.0, f32::INFINITY];

// ---------------------------------------------------------------------------------------------
// A copy of the kernel's lobe (kernel/src/light/lobe.rs) with LOBE_NARROWER as a parameter

/// The receiver's lobe towards one light.
struct CopyLobe {
    frame: Frame,
    wo: Vec3,
    slopes: SlopeBox,
}

impl CopyLobe {
    /// `Lobe::towards` (spheres and quads present) with `narrower` for `LOBE_NARROWER`.
    fn towards(shape: &Shape, at: &ShadingPoint, narrower: f32) -> Option<Self> {
        let Material::GgxConductor { alpha, .. } = at.bsdf else { return None };
        let (x, n, wo) = (at.p, at.n, at.wo);
        let (center, radius) = match shape.as_sphere() {
            Some(sphere) => sphere,
            None => (shape.centroid(), shape.bounding_radius()),
        };
        let to_c = center - x;
        let d2 = dot(to_c, to_c);
        let r2 = radius * radius;
        let sin_max = sqrt(r2 / d2);
        if !(d2 > r2 * CLEAR && alpha < narrower * sin_max) {
            return None;
        }
        let frame = Frame::from_normal(n);
        let wo = frame.to_local(wo);
        let slopes = match (shape.as_sphere(), shape.corners()) {
            (Some(_), _) => {
                let axis = frame.to_local(to_c / sqrt(d2));
                SlopeBox::facing_cone(wo, alpha, axis, 1.0 - cone_one_minus_cos(r2 / d2), sin_max)
            }
            (None, Some(c)) => {
                let corners = c.map(|p| frame.to_local(p - x));
                let edge = nearest_edge(Vec3::new(-wo.x, -wo.y, wo.z), &corners)?;
                if !(edge.sine > -LOBE_REACH * alpha && edge.sine < 2.0 * LOBE_INSIDE * alpha) {
                    return None;
                }
                let mid = |a: Vec3, b: Vec3| (a + b) * 0.5;
                let [c0, c1, c2, c3] = corners;
                let points = [c0, mid(c0, c1), c1, mid(c1, c2), c2, mid(c2, c3), c3, mid(c3, c0)];
                let outline = points.map(|p| p / sqrt(dot(p, p)));
                SlopeBox::facing_edge(wo, alpha, &edge, &outline)
            }
            (None, None) => None,
        }?;
        if slopes.holds_disc(LOBE_INSIDE * alpha) {
            return None;
        }
        Some(CopyLobe { frame, wo, slopes })
    }

    fn sample(&self, u: Vec2) -> Option<Vec3> {
        sample_ggx_reflection_in(self.wo, &self.slopes, u).map(|wi| self.frame.to_world(wi))
    }

    fn pdf(&self, wi: Vec3) -> f32 {
        ggx_reflection_in_pdf(self.wo, &self.slopes, self.frame.to_local(wi))
    }
}

/// The light technique with lobe mixing at `candidate`: `LightSampler::sample` and `pdf` of the
/// kernel (kernel/src/light/sampler.rs) with the candidate's share and bound.
struct Mixture<'a> {
    own: OwnSampler<'a>,
    candidate: Candidate,
}

impl Mixture<'_> {
    fn lobe(
        &self,
        light: LightId,
        at: &ShadingPoint,
    ) -> Option<(CopyLobe, f32, &Shape, Rgb, picomis::ShapeId)> {
        let (share, narrower) = self.candidate?;
        let scene = self.own.scene();
        let light = scene.light(light)?;
        let Light::Area { radiance, shape: emitter } = *light else { return None };
        let shape = scene.light_shape(light)?;
        let lobe = CopyLobe::towards(shape, at, narrower)?;
        Some((lobe, share, shape, radiance, emitter))
    }

    fn sample(&self, light: LightId, at: &ShadingPoint, u: Vec2) -> Option<LightSample> {
        let Some((lobe, share, shape, radiance, emitter)) = self.lobe(light, at) else {
            return self.own.sample(light, at, u);
        };
        let own = 1.0 - share;
        let from_lobe = u.x >= own;
        let s = if !from_lobe {
            self.own.sample(light, at, Vec2::new(u.x / own, u.y))?
        } else {
            let ray = Ray { origin: at.p, dir: lobe.sample(Vec2::new((u.x - own) / share, u.y))? };
            let distance = shape.intersect(&ray, 0.0, f32::INFINITY)?;
            let y = SurfacePoint { p: ray.at(distance), n: shape.normal_at(ray.at(distance)) };
            if !(dot(y.n, ray.dir) < 0.0) {
                return None;
            }
            let pdf = self.own.pdf(light, at, &y);
            LightSample { wi: ray.dir, distance, radiance, pdf, delta: false, emitter: Some(emitter) }
        };
        let lobe_pdf = lobe.pdf(s.wi);
        if from_lobe && !(lobe_pdf > 0.0) {
            return None;
        }
        let pdf = own * s.pdf + share * lobe_pdf;
        (pdf.is_finite() && pdf > 0.0).then_some(LightSample { pdf, ..s })
    }

    fn pdf(&self, light: LightId, at: &ShadingPoint, y: &SurfacePoint) -> f32 {
        let own = self.own.pdf(light, at, y);
        let Some((lobe, share, ..)) = self.lobe(light, at) else { return own };
        let v = y.p - at.p;
        let d2 = dot(v, v);
        if !(d2 > 0.0) {
            return 0.0;
        }
        (1.0 - share) * own + share * lobe.pdf(v / sqrt(d2))
    }
}

// ---------------------------------------------------------------------------------------------
// A copy of the kernel's multi-sample estimator (as in the `beyond` example), power heuristic

/// The reflected light of camera sample `index` of pixel (x, y).
fn camera_sample(m: &Mixture<'_>, settings: &RenderSettings, x: u32, y: u32, index: u32) -> Rgb {
    let scene = m.own.scene();
    let film = scene.film();
    let mut sampler = Sampler::with_kind(settings.sampler(), settings.seed(), y * film.width() + x, index);
    let jitter = sampler.next_2d();
    let (ray, t_near) = scene.camera().ray_at_pixel(Vec2::new(x as f32 + jitter.x, y as f32 + jitter.y));
    match scene.intersect(&ray, t_near, f32::INFINITY, None) {
        Some(hit) if hit.front => direct(m, settings.method(), &hit, -ray.dir, &mut sampler),
        _ => Rgb::ZERO,
    }
}

/// The kernel's bound on one sample's contribution.
fn bounded(c: Rgb) -> Rgb {
    let ok = |v: f32| v.abs() <= picomis::MAX_CONTRIBUTION;
    if ok(c.x) && ok(c.y) && ok(c.z) { c } else { Rgb::ZERO }
}

fn direct(m: &Mixture<'_>, method: Method, x: &Hit, wo_world: Vec3, sampler: &mut Sampler) -> Rgb {
    let (lights, scene) = (&m.own, m.own.scene());
    let mut sum = Rgb::ZERO;
    let Some(bsdf) = scene.material(x.object).filter(|m| !m.is_black()) else { return sum };
    // The receiver as the kernel's estimator sees it: its BSDF from wo (`Outgoing`).
    let frame = Frame::from_normal(x.point.n);
    let at = ShadingPoint { p: x.point.p, n: x.point.n, wo: wo_world, bsdf: *bsdf };
    let seen = bsdf.seen_from(bsdf.to_local(&frame, wo_world));
    let selection = lights.selection_at(&at);
    let (u_select, v) = sampler.next_2d_reusable();
    if let Some((chosen, ls)) = lights
        .select_reusing(&selection, u_select)
        .and_then(|(c, u)| Some((c, m.sample(c.light, &at, Vec2::new(u, v))?)))
    {
        let p_light = chosen.probability * ls.pdf;
        let (f, p_bsdf) = seen.eval_pdf(bsdf.to_local(&frame, ls.wi));
        let shadow = Ray { origin: at.p, dir: ls.wi };
        if f != Rgb::ZERO
            && ls.radiance != Rgb::ZERO
            && scene.unoccluded(&shadow, ls.distance, x.object, ls.emitter)
        {
            let w = if ls.delta { 1.0 } else { method.weight(Technique::Light, p_light, p_bsdf) };
            sum += bounded(f * ls.radiance * (w / p_light));
        }
    }
    if let Some(bs) = seen.sample(sampler.next_2d()) {
        let ray = Ray { origin: at.p, dir: frame.to_world(bs.wi) };
        if let Some((y, light, radiance)) = scene.emitter_hit(&ray, x.object) {
            if radiance != Rgb::ZERO {
                let p_light = lights.pmf(&selection, light) * m.pdf(light, &at, &y.point);
                let w = method.weight(Technique::Bsdf, p_light, seen.pdf(bs.wi));
                sum += bounded(bs.weight * radiance * w);
            }
        }
    }
    sum
}

// ---------------------------------------------------------------------------------------------
// Measuring

fn rgb64(c: Rgb) -> [f64; 3] {
    [f64::from(c.x), f64::from(c.y), f64::from(c.z)]
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

/// The reflected light of every pixel by `sample` (camera sample `index` of pixel (x, y)).
fn render(film: Film, spp: u32, sample: impl Fn(u32, u32, u32) -> Rgb + Sync) -> Vec<[f64; 3]> {
    (0..film.pixels())
        .into_par_iter()
        .map(|i| {
            let (x, y) = (i % film.width(), i / film.width());
            let mut sum = [0.0; 3];
            for s in 0..spp {
                let r = rgb64(sample(x, y, s));
                (0..3).for_each(|c| sum[c] += r[c] / f64::from(spp));
            }
            sum
        })
        .collect()
}

/// The reference (the kernel's balance heuristic, quads in solid angle) in two halves and its own
/// relative MSE; cached as the `beyond` example caches it (the same estimator and files).
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
        let kernel = picomis_host::renderer(scene, &settings).expect("settings the kernel accepts");
        let kernel = &*kernel;
        let image = render(film, settings.spp(), |x, y, s| {
            let e = kernel.camera_sample(x, y, s);
            e.light.contribution + e.bsdf.contribution
        });
        let bytes: Vec<u8> = image.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
        let _ = std::fs::write(&path, bytes);
        image
    };
    let (a, b) = (half(0), half(1));
    let r: Vec<[f64; 3]> = a.iter().zip(&b).map(|(a, b)| [0, 1, 2].map(|c| 0.5 * (a[c] + b[c]))).collect();
    (r, rel_mse(&a, &b) / 4.0)
}

/// The scene's film scaled down to at most 128 x 96 pixels' worth.
fn study_film(file: &SceneFile) -> Film {
    let f = file.film();
    let scale = (128.0 * 96.0 / f64::from(f.pixels())).sqrt().min(1.0);
    let side = |v: u32| ((f64::from(v) * scale).round() as u32).max(1);
    Film::new(side(f.width()), side(f.height())).expect("a valid film")
}

/// The settings the copy implements: the best preset's strategies without the control variate,
/// with lobe mixing `lobe` (the kernel's, to check the copy against).
fn settings(spp: u32, seed: u32, lobe: LobeMixing) -> RenderSettings {
    let best = Preset::Best.settings();
    RenderSettings::new(best.method(), 1, 1, spp, seed)
        .and_then(|s| s.with_control_variate(ControlVariate::Off))
        .expect("valid settings")
        .with_light_selection(LightSelection::Contribution)
        .with_sphere_sampling(SphereSampling::Cone)
        .with_quad_sampling(QuadSampling::Area)
        .with_lobe_mixing(lobe)
}

fn label(c: Candidate) -> String {
    match c {
        None => "off".into(),
        Some((s, n)) if n.is_infinite() => format!("share {s}, every GGX receiver"),
        Some((s, n)) => format!("share {s}, alpha < {n} sin"),
    }
}

/// Relative MSE of every candidate on `file` (the first is without lobe mixing).
fn measure(file: &SceneFile, candidates: &[Candidate], spp: u32, seeds: u32, ref_spp: u32) -> Vec<f64> {
    let scene: HostScene = file
        .build_with_film::<HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS>(study_film(file))
        .unwrap_or_else(|e| panic!("{e}"));
    let film = scene.film();

    // The copy at the kernel's constants gives the kernel's camera samples, bit for bit.
    let kernel_settings = settings(1, 7, LobeMixing::On);
    let kernel = picomis_host::renderer(&scene, &kernel_settings).expect("settings the kernel accepts");
    let copy = Mixture { own: OwnSampler::new(&scene), candidate: Some(KERNEL) };
    let mut checked = 0;
    for i in (0..film.pixels()).step_by(7) {
        let (x, y) = (i % film.width(), i / film.width());
        for s in 0..4 {
            let e = kernel.camera_sample(x, y, s);
            let mine = camera_sample(&copy, &kernel_settings, x, y, s);
            assert_eq!(
                mine,
                e.light.contribution + e.bsdf.contribution,
                "{}: pixel ({x}, {y}) sample {s}",
                file.name()
            );
            checked += 1;
        }
    }

    let (r, noise) = reference(file.name(), &scene, ref_spp);
    println!(
        "\n{} ({}x{}, {spp} spp, {seeds} seeds, sobol; the copy checked against the kernel on {checked} camera \
         samples; reference {ref_spp} spp, its noise {noise:.2e} subtracted)",
        file.name(),
        film.width(),
        film.height()
    );
    candidates
        .iter()
        .map(|&candidate| {
            let m = Mixture { own: OwnSampler::new(&scene), candidate };
            let mut sum = 0.0;
            for seed in 0..seeds {
                let s = settings(spp, 1 + seed, LobeMixing::Off);
                sum += rel_mse(&render(film, spp, |x, y, i| camera_sample(&m, &s, x, y, i)), &r) - noise;
            }
            sum / f64::from(seeds)
        })
        .collect()
}

fn main() {
    let mut args = std::env::args().skip(1);
    let (mut spp, mut seeds, mut ref_spp, mut names) = (64, 4, 8192, Vec::new());
    while let Some(a) = args.next() {
        let mut value = || args.next().unwrap_or_else(|| panic!("{a} needs a value"));
        match a.as_str() {
            "--spp" => spp = value().parse().expect("--spp N"),
            "--seeds" => seeds = value().parse().expect("--seeds K"),
            "--ref-spp" => ref_spp = value().parse().expect("--ref-spp N"),
            _ => names.push(a),
        }
    }
    if names.is_empty() {
        names = ["veach_mis", "stress", "tests/scenes/mirror_lights.json", "tests/scenes/glossy_lights.json"]
            .map(String::from)
            .to_vec();
    }
    let builtins = builtin_scenes();
    let files: Vec<SceneFile> = names
        .iter()
        .map(|n| match builtins.iter().find(|f| f.name() == n) {
            Some(f) => f.clone(),
            None => SceneFile::load(&PathBuf::from(n)).unwrap_or_else(|e| panic!("{e}")),
        })
        .collect();
    let mut candidates: Vec<Candidate> = vec![None];
    candidates.extend(SHARES.iter().flat_map(|&s| NARROWER.iter().map(move |&n| Some((s, n)))));
    let at_kernel =
        candidates.iter().position(|c| *c == Some(KERNEL)).expect("the kernel's pair is a candidate");

    let mut all = Vec::new();
    for file in &files {
        let errors = measure(file, &candidates, spp, seeds, ref_spp);
        let header: Vec<String> = NARROWER
            .iter()
            .map(|n| if n.is_infinite() { "every GGX".into() } else { format!("alpha < {n} sin") })
            .collect();
        println!("| lobe share | {} |", header.join(" | "));
        println!("|---|{}", "---:|".repeat(NARROWER.len()));
        for (i, s) in SHARES.iter().enumerate() {
            let row: Vec<String> = (0..NARROWER.len())
                .map(|j| {
                    let k = 1 + i * NARROWER.len() + j;
                    let mark = if k == at_kernel { " (kernel)" } else { "" };
                    format!("{:.3e}{mark}", errors[k])
                })
                .collect();
            println!("| {s} | {} |", row.join(" | "));
        }
        println!("without lobe mixing: {:.3e}", errors[0]);
        all.push(errors);
    }
    println!(
        "\nEach candidate's relative MSE over the kernel's pair ({}), geometric mean over the scenes:",
        label(Some(KERNEL))
    );
    let mut ranked: Vec<(f64, Candidate)> = candidates
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            let logs: f64 = all.iter().map(|e| (e[k] / e[at_kernel]).ln()).sum();
            ((logs / all.len() as f64).exp(), c)
        })
        .collect();
    ranked.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (ratio, c) in ranked {
        let per: Vec<String> = all
            .iter()
            .map(|e| format!("{:.3}", e[candidates.iter().position(|x| *x == c).unwrap_or(0)] / e[at_kernel]))
            .collect();
        println!("| {} | {ratio:.3} | {} |", label(c), per.join(" | "));
    }
}
