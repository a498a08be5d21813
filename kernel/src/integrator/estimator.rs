//! The MIS direct-lighting estimator of the lecture (Veach and Guibas 1995), multi-sample model
//! (and the one-sample model of section 4, see [`crate::integrator::model`]):
//!
//! F = 1/n_l sum_j w_l(X_j) f(X_j)/p_l(X_j) + 1/n_b sum_j w_b(Y_j) f(Y_j)/p_b(Y_j),
//!
//! with f = L_e f_r cos(theta_i) over directions at the shading point, p_l = P(light) p_w the light
//! technique's pdf (the light sampler's selection probability times its pdf per unit solid angle),
//! p_b the BSDF's pdf, and w the weights of [`Method`] on q_i = n_i p_i. Each
//! technique's weighted contribution and weights are kept apart, so the lecture's weight and
//! contribution images come from this one function.

use crate::geometry::Ray;
use crate::integrator::closed_form;
use crate::integrator::mis::{Method, Technique};
use crate::integrator::model::MisModel;
use crate::integrator::settings::{ControlVariate, RenderSettings};
use crate::light::{LightSampler, SelectionAt, ShadingPoint};
use crate::num::{Frame, Rgb, Vec2, Vec3};
use crate::query::accel::{POINT_TERMS, PointRays};
use crate::sampling::sampler::Sampler;
use crate::scene::Light;
use crate::scene::LightId;
use crate::scene::{Hit, Scene};
use crate::scene::{Material, Outgoing};

/// The largest contribution one sample may add (per channel, already divided by the technique's
/// sample count); a larger one is dropped like a NaN or an infinity. The bound keeps every
/// running sum finite: at most 2^16 samples per technique per camera sample and 2^32 camera
/// samples per pixel give at most 2^48 x 1e22 ~ 2.8e36 per part, and the three parts of
/// [`Estimate::radiance`] (emitted light is at most [`MAX_EMISSION`](crate::scene::MAX_EMISSION))
/// stay far below `f32::MAX` ~ 3.4e38. Valid scenes reach it only with emission near the
/// maximum seen through a pdf near zero.
pub const MAX_CONTRIBUTION: f32 = 1e22;

/// One technique's share of an estimate.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TechniqueEstimate {
    /// Weighted contribution, already divided by the technique's sample count.
    pub contribution: Rgb,
    /// Sum of the MIS weights of the samples that found light.
    pub weight_sum: f32,
    /// Number of samples that found light (non-zero integrand).
    pub found: u32,
}

impl TechniqueEstimate {
    #[inline]
    fn add(&mut self, contribution: Rgb, weight: f32) {
        // Never let a NaN or infinity leave the estimator, nor a value that could overflow a sum.
        let bounded = |v: f32| v.abs() <= MAX_CONTRIBUTION; // false for NaN
        if bounded(contribution.x) && bounded(contribution.y) && bounded(contribution.z) {
            self.contribution += contribution;
            self.weight_sum += weight;
            self.found = self.found.saturating_add(1);
        }
    }

    /// Mean weight of the samples that found light (0 when none did).
    pub fn mean_weight(&self) -> f32 {
        if self.found > 0 { self.weight_sum / self.found as f32 } else { 0.0 }
    }

    fn merge(&mut self, other: &Self) {
        self.contribution += other.contribution;
        self.weight_sum += other.weight_sum;
        self.found = self.found.saturating_add(other.found);
    }
}

/// Radiance estimate of a camera sample or a pixel, split by where it came from.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Estimate {
    /// Radiance emitted by the surface the camera sees.
    pub emitted: Rgb,
    /// Direct light found by light sampling.
    pub light: TechniqueEstimate,
    /// Direct light found by BSDF sampling.
    pub bsdf: TechniqueEstimate,
}

impl Estimate {
    /// Total radiance.
    #[inline]
    pub fn radiance(&self) -> Rgb {
        self.emitted + self.light.contribution + self.bsdf.contribution
    }

    /// Adds another estimate (for averaging camera samples).
    pub fn merge(&mut self, other: &Self) {
        self.emitted += other.emitted;
        self.light.merge(&other.light);
        self.bsdf.merge(&other.bsdf);
    }

    /// Scales the radiance parts by `s` (weights and counts are left as sums).
    pub fn scale(&mut self, s: f32) {
        self.emitted *= s;
        self.light.contribution *= s;
        self.bsdf.contribution *= s;
    }
}

/// Radiance arriving along a camera ray: emission of the first hit plus its direct lighting.
#[inline]
pub fn trace<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    ray: &Ray,
    t_near: f32,
    sampler: &mut Sampler,
) -> Estimate {
    shade(scene, settings, scene.intersect(ray, t_near, f32::INFINITY, None), ray.dir, sampler)
}

/// Radiance arriving along a ray in direction `dir` whose first hit is `hit` ([`trace`] once
/// the ray is traced): emission plus direct lighting.
#[inline]
pub fn shade<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    hit: Option<Hit>,
    dir: Vec3,
    sampler: &mut Sampler,
) -> Estimate {
    let Some(hit) = hit else {
        return Estimate::default();
    };
    if !hit.front {
        return Estimate::default(); // one-sided: nothing is emitted or reflected towards the back
    }
    let emitted = match scene.emitter(hit.object) {
        Some((_, Light::Area { radiance, .. })) => *radiance,
        _ => Rgb::ZERO,
    };
    let (light, bsdf) = estimate_direct(scene, settings, &hit, -dir, sampler);
    Estimate { emitted, light, bsdf }
}

/// Direct lighting at `x` towards `wo`, by light sampling and BSDF sampling combined with MIS,
/// in the settings' model: [`estimate_direct_multi_sample`] or [`estimate_direct_one_sample`].
/// With the control variate on, a Lambertian receiver gets the unoccluded light of every quad
/// and sphere light in closed form, in the light part, and the techniques sample only
/// f (V - 1) for those lights ([`crate::integrator::closed_form`]).
#[inline]
pub fn estimate_direct<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    x: &Hit,
    wo: Vec3,
    sampler: &mut Sampler,
) -> (TechniqueEstimate, TechniqueEstimate) {
    let none = (TechniqueEstimate::default(), TechniqueEstimate::default());
    // On the microcontrollers not through `Shading::new`, whose `Option` cost a copy of the
    // struct on the M4F (some 100 instructions). On x86 the other way round: that struct built
    // by a function of its own made the render 15 % slower.
    #[cfg(target_os = "none")]
    let at = match reflecting(scene, x) {
        Some(bsdf) => Shading::with_bsdf(scene, settings, x, bsdf, wo),
        None => return none,
    };
    #[cfg(not(target_os = "none"))]
    let Some(at) = Shading::new(scene, settings, x, wo) else { return none };
    let (mut by_light, by_bsdf) = match settings.mis_model() {
        MisModel::Multi => estimate_direct_multi_sample(scene, settings, &at, sampler),
        MisModel::One { .. } => estimate_direct_one_sample(scene, settings, &at, sampler),
    };
    // The closed-form part of the control variate (zero without it).
    by_light.contribution += at.unoccluded;
    (by_light, by_bsdf)
}

/// The multi-sample model: F = sum_i 1/n_i sum_j w_i(X_ij) f(X_ij) / p_i(X_ij), q_i = n_i p_i.
#[inline]
pub fn estimate_direct_multi_sample<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    at: &Shading<'_, L>,
    sampler: &mut Sampler,
) -> (TechniqueEstimate, TechniqueEstimate) {
    let (mut by_light, mut by_bsdf) = (TechniqueEstimate::default(), TechniqueEstimate::default());
    let method = settings.method();
    let (n_l, n_b) = settings.technique_samples();
    let (n_light, n_bsdf) = (f32::from(n_l), f32::from(n_b));
    // Shadow and BSDF rays all start at x: what their tests need of x alone, computed once.
    at.with_rays(scene, |from_x| {
        // Technique 1, light sampling: a light, y on it, visibility, w_l L_e f cos / (n_l p_l).
        for _ in 0..n_l {
            if let Some(s) = light_sample(scene, settings, at, from_x, sampler) {
                add_light_sample(&mut by_light, method, &s, n_light, n_bsdf);
            }
        }

        // Technique 2, BSDF sampling: wi ~ p_b, trace; if a light's front side is hit,
        // w_b L_e f cos / (n_b p_b), with p_l evaluated for the light that was hit.
        for _ in 0..n_b {
            bsdf_sample(scene, settings, at, from_x, sampler, |s| {
                add_bsdf_sample(&mut by_bsdf, method, &s, n_light, n_bsdf)
            });
        }
    });
    (by_light, by_bsdf)
}

/// The one-sample model: pick the light technique with probability c_l (else the BSDF technique,
/// c_b = 1 - c_l), draw one sample X from it, F = w_i(X) f(X) / (c_i p_i(X)), q_i = c_i p_i.
/// (Out of line: its rays from x do not add to the stack frame of the multi-sample model's.)
#[inline(never)]
pub fn estimate_direct_one_sample<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    at: &Shading<'_, L>,
    sampler: &mut Sampler,
) -> (TechniqueEstimate, TechniqueEstimate) {
    let (mut by_light, mut by_bsdf) = (TechniqueEstimate::default(), TechniqueEstimate::default());
    let method = settings.method();
    let c_light = settings.c_light();
    let c_bsdf = 1.0 - c_light;
    // The multi-sample formulas with n_i replaced by c_i, for one sample of one technique.
    at.with_rays(scene, |from_x| {
        if sampler.next_f32() < c_light {
            if let Some(s) = light_sample(scene, settings, at, from_x, sampler) {
                add_light_sample(&mut by_light, method, &s, c_light, c_bsdf);
            }
        } else {
            bsdf_sample(scene, settings, at, from_x, sampler, |s| {
                add_bsdf_sample(&mut by_bsdf, method, &s, c_light, c_bsdf)
            });
        }
    });
    (by_light, by_bsdf)
}

/// Adds a light sample's weighted contribution w_l f / (m_l p_l), with the weight on
/// q_l = m_l p_l and q_b = m_b p_b (m: sample counts, or technique probabilities in the one-sample
/// model). A delta light cannot be hit by a BSDF sample: its weight is one.
#[inline]
fn add_light_sample(to: &mut TechniqueEstimate, method: Method, s: &Found, m_light: f32, m_bsdf: f32) {
    let w =
        if s.delta { 1.0 } else { method.weight(Technique::Light, m_light * s.pdf, m_bsdf * s.pdf_other) };
    to.add(s.value * (w / (m_light * s.pdf)), w);
}

/// Adds a BSDF sample's weighted contribution w_b f / (m_b p_b) (`value` is already f / p_b),
/// with the weight on q_l = m_l p_l and q_b = m_b p_b.
#[inline]
fn add_bsdf_sample(to: &mut TechniqueEstimate, method: Method, s: &Found, m_light: f32, m_bsdf: f32) {
    let w = method.weight(Technique::Bsdf, m_light * s.pdf_other, m_bsdf * s.pdf);
    to.add(s.value * (w / m_bsdf), w);
}

/// The shading point `x` (on a surface of non-black material `bsdf`) seen from `wo`: the one body
/// of [`Shading::new`] and, on the microcontrollers, of `Shading::with_bsdf` (a macro, not a
/// function both call: see [`estimate_direct`]).
macro_rules! shading {
    ($scene:expr, $settings:expr, $x:expr, $bsdf:expr, $wo:expr) => {{
        let (scene, settings, x, bsdf, wo): (_, &RenderSettings, &Hit, &Material, Vec3) =
            ($scene, $settings, $x, $bsdf, $wo);
        let frame = Frame::from_normal(x.point.n);
        let point = ShadingPoint { p: x.point.p, n: x.point.n, wo, bsdf: *bsdf };
        let wo = bsdf.to_local(&frame, wo);
        // On the microcontrollers the selection by contribution reads a copy of the point: lent
        // to the out-of-line selection, `point` itself would be built apart and copied into the
        // struct after (some 100 instructions per shading point on the M4F). The other
        // selections take no copy (6 instructions on the M4F), nor does x86, where it would cost.
        let lights = light_sampler(scene, settings);
        let selection = if cfg!(target_os = "none") && lights.selects_locally() {
            let copy = point;
            lights.selection_in(&copy, &frame, wo)
        } else {
            lights.selection_in(&point, &frame, wo)
        };
        let control_variate =
            settings.control_variate() == ControlVariate::On && matches!(bsdf, Material::Lambertian { .. });
        let (covered, unoccluded) = if control_variate {
            closed_form::unoccluded_light(scene, bsdf, x, wo.z)
        } else {
            (0, Rgb::ZERO)
        };
        let seen = bsdf.seen_from(wo);
        Shading { x, bsdf, frame, seen, point, selection, control_variate, covered, unoccluded }
    }};
}

/// A shading point as the techniques see it: the BSDF seen from `wo` in the local frame, and
/// the light selection there (`L`: the scene's light capacity).
#[derive(Clone, Debug)]
pub struct Shading<'a, const L: usize> {
    x: &'a Hit,
    bsdf: &'a Material,
    frame: Frame,
    /// The BSDF seen from `wo` in the local frame: what f cos and the pdf need of `wo` alone,
    /// computed once for the light and BSDF samples.
    seen: Outgoing,
    /// The shading point as the light sampler sees it (world `wo`).
    point: ShadingPoint,
    /// Light selection here, shared by light samples and the BSDF samples' weights.
    selection: SelectionAt<L>,
    /// The control variate applies here (it is on and the receiver is Lambertian).
    control_variate: bool,
    /// Bit i: light i's unoccluded part is in closed form here.
    covered: u64,
    /// The closed-form reflected radiance of those lights.
    unoccluded: Rgb,
}

impl<'a, const L: usize> Shading<'a, L> {
    /// The shading point `x` seen from `wo`; `None` when its material reflects nothing.
    #[inline]
    pub fn new<const S: usize, const M: usize>(
        scene: &'a Scene<S, L, M>,
        settings: &RenderSettings,
        x: &'a Hit,
        wo: Vec3,
    ) -> Option<Self> {
        let bsdf = reflecting(scene, x)?;
        Some(shading!(scene, settings, x, bsdf, wo))
    }

    /// [`Shading::new`] for the shading point's (non-black) material `bsdf` (see
    /// [`estimate_direct`]).
    #[cfg(target_os = "none")]
    #[inline]
    fn with_bsdf<const S: usize, const M: usize>(
        scene: &'a Scene<S, L, M>,
        settings: &RenderSettings,
        x: &'a Hit,
        bsdf: &'a Material,
        wo: Vec3,
    ) -> Self {
        shading!(scene, settings, x, bsdf, wo)
    }

    /// `f` of the shadow and BSDF rays from here, with the origin terms their queries need: with
    /// the control variate, whose BSDF rays look for every emitter along them, those of all
    /// objects; else those of the objects the culled queries may test. (Where the rays keep no
    /// origin terms, that is one case.)
    #[inline(always)]
    fn with_rays<const S: usize, const M: usize, R>(
        &self,
        scene: &Scene<S, L, M>,
        f: impl FnOnce(&PointRays<S>) -> R,
    ) -> R {
        let among =
            if self.control_variate || !POINT_TERMS { u32::MAX } else { scene.reachable(self.x.object) };
        scene.with_rays_among(self.x.point.p, among, f)
    }

    /// Whether light `light`'s part is sampled as f (V - 1) (its unoccluded part is in closed form).
    #[inline]
    fn analytic(&self, light: LightId) -> bool {
        let i = light.index();
        // (`covered` is 0 without the control variate: skip the 64-bit shift then.)
        self.control_variate && i < 64 && self.covered & (1 << i) != 0
    }
}

/// The material of the surface `x` hit, if it reflects anything.
#[inline]
fn reflecting<'a, const S: usize, const L: usize, const M: usize>(
    scene: &'a Scene<S, L, M>,
    x: &Hit,
) -> Option<&'a Material> {
    scene.material(x.object).filter(|m| !m.is_black())
}

/// The light sampler of the settings' strategies.
#[inline]
fn light_sampler<'a, const S: usize, const L: usize, const M: usize>(
    scene: &'a Scene<S, L, M>,
    settings: &RenderSettings,
) -> LightSampler<'a, S, L, M> {
    LightSampler::new(scene, settings.light_selection(), settings.sphere_sampling())
        .with_quad_sampling(settings.quad_sampling())
        .with_lobe_mixing(settings.lobe_mixing())
}

/// A sample that found light: its integrand value (not divided by any pdf for light samples;
/// divided by the BSDF pdf for BSDF samples), its own technique's pdf and the other's.
struct Found {
    value: Rgb,
    pdf: f32,
    pdf_other: f32,
    delta: bool,
}

/// One light sample: a light and a point on it, f L_e, with V (or V - 1 for a light in closed
/// form); `None` when it carries nothing.
#[inline]
fn light_sample<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    at: &Shading<'_, L>,
    from_x: &PointRays<S>,
    sampler: &mut Sampler,
) -> Option<Found> {
    let lights = light_sampler(scene, settings);
    // One 2-D request: its first number chooses the light and, rescaled, places the point.
    let (u_select, v) = sampler.next_2d_reusable();
    let (chosen, u) = lights.select_reusing(&at.selection, u_select)?;
    let ls = lights.sample(chosen.light, &at.point, Vec2::new(u, v))?;
    // The light technique's pdf of this direction: p_l = P(light) p_w(wi | light).
    let p_light = chosen.probability * ls.pdf;
    let wi = at.bsdf.to_local(&at.frame, ls.wi);
    let (f, p_bsdf) = at.seen.eval_pdf(wi);
    if f == Rgb::ZERO || ls.radiance == Rgb::ZERO {
        return None;
    }
    let visible =
        scene.unoccluded_from(from_x, ls.wi, ls.distance, at.x.object, ls.emitter, Some(chosen.light));
    let value = match (at.analytic(chosen.light), visible) {
        (false, true) => f * ls.radiance,
        (true, false) => -(f * ls.radiance),
        (false, false) | (true, true) => return None,
    };
    Some(Found { value, pdf: p_light, pdf_other: p_bsdf, delta: ls.delta })
}

/// One BSDF sample: wi ~ p_b, traced; `found` is called for each light it counts for, with
/// f L_e / p_b. Without the control variate that is the first surface, if it is a light's front
/// side. With it, a light in closed form counts with f L_e (V - 1) / p_b: only when the ray meets
/// its front side behind another surface.
///
/// Out of line (inlined into the multi-sample model's loop, its loop-invariant values were
/// spilled around it on the M4F), except on RV32IMC, where its own frame would add some
/// 100 bytes to the peak stack.
#[cfg_attr(not(target_arch = "riscv32"), inline(never))]
#[cfg_attr(target_arch = "riscv32", inline)]
fn bsdf_sample<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    at: &Shading<'_, L>,
    from_x: &PointRays<S>,
    sampler: &mut Sampler,
    mut found: impl FnMut(Found),
) {
    let Some(bs) = at.seen.sample(sampler.next_2d()) else { return };
    let wi = at.frame.to_world(bs.wi);
    // The weight needs p_b as a function of the direction, the same function the light
    // technique's weight used (`eval_pdf`), so the two weights of a direction sum to one
    // exactly. (`bs.pdf`, from the sampled half vector, can differ from it by rounding at
    // grazing near-mirror angles; the sample's f / p_b, `bs.weight`, uses the exact one.)
    let pdf = || at.seen.pdf(bs.wi);
    // The light technique's pdf of the direction to y on `light`: p_l = P(light) p_w(wi | light).
    let light_pdf = |light, y: &Hit| {
        let lights = light_sampler(scene, settings);
        lights.pmf(&at.selection, light) * lights.pdf(light, &at.point, &y.point)
    };
    if !at.control_variate {
        let Some((y, light, radiance)) = scene.emitter_hit_from::<true>(from_x, wi, at.x.object) else {
            return;
        };
        if radiance == Rgb::ZERO {
            return;
        }
        let (pdf, pdf_other) = (pdf(), light_pdf(light, &y));
        found(Found { value: bs.weight * radiance, pdf, pdf_other, delta: false });
        return;
    }
    let pdf = pdf();
    scene.emitters_along_from(from_x, wi, at.x.object, |y, light, radiance, visible| {
        let value = match (at.analytic(light), visible) {
            (false, true) => bs.weight * radiance,
            (true, false) => -(bs.weight * radiance),
            (false, false) | (true, true) => return,
        };
        if radiance != Rgb::ZERO {
            found(Found { value, pdf, pdf_other: light_pdf(light, &y), delta: false });
        }
    });
}
