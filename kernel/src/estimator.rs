//! The MIS direct-lighting estimator of the lecture (Veach and Guibas 1995), multi-sample model:
//!
//! F = 1/n_l sum_j w_l(X_j) f(X_j)/p_l(X_j) + 1/n_b sum_j w_b(Y_j) f(Y_j)/p_b(Y_j),
//!
//! with f = L_e f_r cos(theta_i) over directions at the shading point, p_l = P(light) p_w the light
//! technique's pdf (the light sampler's selection probability times its pdf per unit solid angle),
//! p_b the BSDF's pdf, and w the weights of [`Method`](crate::Method) on q_i = n_i p_i. Each
//! technique's weighted contribution and weights are kept apart, so the lecture's weight and
//! contribution images come from this one function.

use crate::light::Light;
use crate::light_sampler::{LightSampler, ShadingPoint};
use crate::math::{Frame, Rgb, Vec2, Vec3, finite3};
use crate::mis::Technique;
use crate::rng::Sampler;
use crate::scene::{Hit, Scene};
use crate::settings::RenderSettings;
use crate::shape::Ray;

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
        // Never let a NaN or infinity leave the estimator.
        if finite3(contribution) {
            self.contribution += contribution;
            self.weight_sum += weight;
            self.found += 1;
        }
    }

    /// Mean weight of the samples that found light (0 when none did).
    pub fn mean_weight(&self) -> f32 {
        if self.found > 0 { self.weight_sum / self.found as f32 } else { 0.0 }
    }

    fn merge(&mut self, other: &Self) {
        self.contribution += other.contribution;
        self.weight_sum += other.weight_sum;
        self.found += other.found;
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
    let mut out = Estimate::default();
    let Some(hit) = scene.intersect(ray, t_near, f32::INFINITY, None) else {
        return out;
    };
    if !hit.front {
        return out; // one-sided: nothing is emitted or reflected towards the back
    }
    if let Some((_, Light::Area { radiance, .. })) = scene.emitter(hit.object) {
        out.emitted = *radiance;
    }
    let (light, bsdf) = estimate_direct(scene, settings, &hit, -ray.dir, sampler);
    out.light = light;
    out.bsdf = bsdf;
    out
}

/// Direct lighting at `x` towards `wo`, by light sampling and BSDF sampling combined with MIS.
#[inline]
pub fn estimate_direct<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    x: &Hit,
    wo: Vec3,
    sampler: &mut Sampler,
) -> (TechniqueEstimate, TechniqueEstimate) {
    let (mut by_light, mut by_bsdf) = (TechniqueEstimate::default(), TechniqueEstimate::default());
    let Some(bsdf) = scene.material(x.object).filter(|m| !m.is_black()) else {
        return (by_light, by_bsdf);
    };
    let lights = LightSampler::new(scene, settings.light_selection(), settings.sphere_sampling());
    let method = settings.method();
    let (n_l, n_b) = settings.technique_samples();
    let (n_light, n_bsdf) = (f32::from(n_l), f32::from(n_b));
    let at = ShadingPoint { p: x.point.p, n: x.point.n, wo };
    let frame = Frame::from_normal(x.point.n);
    let wo = frame.to_local(wo);
    let p = x.point.p;

    // Technique 1, light sampling: a light, y on it, visibility, w_l L_e f cos / (n_l p_l).
    for _ in 0..n_l {
        let u_select = sampler.next_f32();
        let u: Vec2 = sampler.next_2d();
        let Some(chosen) = lights.select(&at, u_select) else { continue };
        let Some(ls) = lights.sample(chosen.light, p, u) else { continue };
        // The light technique's pdf of this direction: p_l = P(light) p_w(wi | light).
        let p_light = chosen.probability * ls.pdf;
        let wi = frame.to_local(ls.wi);
        let (f, p_bsdf) = bsdf.eval_pdf(wo, wi);
        if f == Rgb::ZERO || ls.radiance == Rgb::ZERO {
            continue;
        }
        let shadow = Ray { origin: p, dir: ls.wi };
        if !scene.unoccluded(&shadow, ls.distance, x.object, ls.emitter) {
            continue;
        }
        // A delta light cannot be hit by a BSDF sample: its weight is one.
        let w =
            if ls.delta { 1.0 } else { method.weight(Technique::Light, n_light * p_light, n_bsdf * p_bsdf) };
        by_light.add(f * ls.radiance * (w / (n_light * p_light)), w);
    }

    // Technique 2, BSDF sampling: wi ~ p_b, trace; if a light's front side is hit,
    // w_b L_e f cos / (n_b p_b), with p_l evaluated for the light that was hit.
    for _ in 0..n_b {
        let Some(bs) = bsdf.sample(wo, sampler.next_2d()) else { continue };
        let ray = Ray { origin: p, dir: frame.to_world(bs.wi) };
        let Some((y, light, radiance)) = scene.emitter_hit(&ray, x.object) else { continue };
        if radiance == Rgb::ZERO {
            continue;
        }
        let p_light = lights.pmf(&at, light) * lights.pdf(light, p, &y.point);
        // The weight needs p_b as a function of the direction, the same function the light
        // technique's weight used (`eval_pdf`), so the two weights of a direction sum to one
        // exactly. (`bs.pdf`, from the sampled half vector, can differ from it by rounding at
        // grazing near-mirror angles; the sample's f / p_b, `bs.weight`, uses the exact one.)
        let p_bsdf = bsdf.pdf(wo, bs.wi);
        let w = method.weight(Technique::Bsdf, n_light * p_light, n_bsdf * p_bsdf);
        by_bsdf.add(bs.weight * radiance * (w / n_bsdf), w);
    }
    (by_light, by_bsdf)
}
