//! Materials: Lambertian and the GGX rough conductor (Fresnel one). One-sided: a material
//! reflects only when both directions are above the geometric normal. Directions are local
//! (`z` = normal), `wo` towards the viewer, `wi` towards the light.

use crate::error::{Field, SceneError};
use crate::num::{Frame, INV_PI, Rgb, Vec2, Vec3, dot, finite3, positive_finite, try_normalize};
use crate::sampling::{GgxAlpha, cosine_hemisphere_pdf, sample_cosine_hemisphere, sample_ggx_vndf};
use crate::words::{Image, Words, float, vec3};

/// The closed set of materials.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Material {
    /// Ideal diffuse reflector: f = albedo / pi.
    Lambertian {
        /// Albedo per channel, in [0, 1].
        albedo: Rgb,
    },
    /// GGX microfacet conductor with Fresnel one: f = R D G1(wi) G1(wo) / (4 cos_i cos_o).
    GgxConductor {
        /// GGX alpha, in (0, 1], used directly.
        alpha: f32,
        /// Specular reflectance R per channel, in [0, 1].
        reflectance: Rgb,
    },
}

/// A direction drawn by BSDF sampling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// Sampled incident direction (local).
    pub wi: Vec3,
    /// f cos(theta_i) / pdf.
    pub weight: Rgb,
    /// Pdf per unit solid angle.
    pub pdf: f32,
}

fn check_reflectance(c: Rgb, field: Field) -> Result<(), SceneError> {
    if !finite3(c) {
        return Err(SceneError::NonFinite(field));
    }
    if c.min_element() < 0.0 || c.max_element() > 1.0 {
        return Err(SceneError::OutOfRange(field));
    }
    Ok(())
}

impl Material {
    /// A Lambertian material; every albedo channel in [0, 1].
    pub fn lambertian(albedo: Rgb) -> Result<Self, SceneError> {
        check_reflectance(albedo, Field::Albedo)?;
        Ok(Material::Lambertian { albedo })
    }

    /// A GGX conductor; alpha in (0, 1], reflectance channels in [0, 1].
    pub fn ggx_conductor(alpha: f32, reflectance: Rgb) -> Result<Self, SceneError> {
        if !alpha.is_finite() {
            return Err(SceneError::NonFinite(Field::Alpha));
        }
        if !(alpha > 0.0 && alpha <= 1.0) {
            return Err(SceneError::OutOfRange(Field::Alpha));
        }
        check_reflectance(reflectance, Field::Reflectance)?;
        Ok(Material::GgxConductor { alpha, reflectance })
    }

    /// True when the material reflects nothing (f = 0 everywhere): direct lighting is skipped.
    #[inline]
    pub fn is_black(&self) -> bool {
        let c = self.albedo_bound();
        // Compare-and-branch rather than `max_element` (an `fmaxf` call on Cortex-M).
        !(c.x > 0.0 || c.y > 0.0 || c.z > 0.0)
    }

    /// The local direction about which f cos gathers for `wo`: the normal for a Lambertian
    /// surface, the mirror direction of `wo` for GGX (where its lobe peaks as alpha goes to 0).
    #[inline]
    pub fn lobe_axis(&self, wo: Vec3) -> Vec3 {
        match self {
            Material::Lambertian { .. } => Vec3::Z,
            Material::GgxConductor { .. } => Vec3::new(-wo.x, -wo.y, wo.z),
        }
    }

    /// A bound of the directional albedo, the integral of f cos over all `wi`, per channel: the
    /// albedo, or the GGX reflectance (G1(wi) <= 1 and the visible normals integrate to one).
    #[inline]
    pub fn albedo_bound(&self) -> Rgb {
        match *self {
            Material::Lambertian { albedo } => albedo,
            Material::GgxConductor { reflectance, .. } => reflectance,
        }
    }

    /// The world direction `v` in `frame`'s local coordinates as far as this material reads
    /// them: a Lambertian surface reads only cos(theta), so its `x` and `y` are left zero and
    /// two of the frame's three dot products are skipped (the same `z`, bit for bit).
    #[inline]
    pub fn to_local(&self, frame: &Frame, v: Vec3) -> Vec3 {
        match self {
            Material::Lambertian { .. } => Vec3::new(0.0, 0.0, dot(v, frame.n)),
            Material::GgxConductor { .. } => frame.to_local(v),
        }
    }

    /// f(wo, wi) cos(theta_i).
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        self.eval_pdf(wo, wi).0
    }

    /// Pdf per unit solid angle with which [`Material::sample`] draws `wi`.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.eval_pdf(wo, wi).1
    }

    /// f(wo, wi) cos(theta_i) and the pdf of `wi`, sharing the half vector, D and G1(wo).
    #[inline]
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (Rgb, f32) {
        self.seen_from(wo).eval_pdf(wi)
    }

    /// The material seen from `wo`: what f cos and the pdf need of `wo` alone, computed once
    /// for many `wi`.
    #[inline]
    pub fn seen_from(&self, wo: Vec3) -> Outgoing {
        let (ggx, pdf_scale) = match *self {
            Material::Lambertian { .. } => (GgxAlpha::new(1.0), 0.0),
            Material::GgxConductor { alpha, .. } => {
                let ggx = GgxAlpha::new(alpha);
                (ggx, if wo.z > 0.0 { ggx.g1(wo) / (4.0 * wo.z) } else { 0.0 })
            }
        };
        Outgoing { material: *self, wo, ggx, pdf_scale }
    }

    /// Draws `wi` for the given `wo`: cosine-weighted (Lambertian) or visible normals (GGX).
    /// `None` when the draw leaves the upper hemisphere or `wo` is below it.
    #[inline]
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        self.seen_from(wo).sample(u)
    }
}

/// A material seen from one `wo` ([`Material::seen_from`]): [`Outgoing::eval_pdf`] gives
/// [`Material::eval_pdf`] for any `wi`, bit for bit, without recomputing the terms of `wo`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outgoing {
    material: Material,
    /// Local direction towards the viewer.
    wo: Vec3,
    /// The GGX roughness (alpha one for Lambertian, unused).
    ggx: GgxAlpha,
    /// G1(wo) / (4 cos_o), the visible-normal pdf of a reflected direction per unit D (GGX
    /// with cos_o > 0; else 0).
    pdf_scale: f32,
}

impl Outgoing {
    /// The material.
    #[inline]
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// The local direction towards the viewer.
    #[inline]
    pub fn wo(&self) -> Vec3 {
        self.wo
    }

    /// G1(wo) / (4 cos_o) (GGX; 0 for Lambertian): a reflected direction's pdf is D(m) times
    /// it, and f cos_i is that pdf times R G1(wi).
    #[inline]
    pub fn pdf_scale(&self) -> f32 {
        self.pdf_scale
    }

    /// f(wo, wi) cos(theta_i) and the pdf of `wi`, sharing the half vector, D and G1(wo).
    #[inline]
    pub fn eval_pdf(&self, wi: Vec3) -> (Rgb, f32) {
        let wo = self.wo;
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return (Rgb::ZERO, 0.0);
        }
        match self.material {
            Material::Lambertian { albedo } => (albedo * (INV_PI * wi.z), cosine_hemisphere_pdf(wi.z)),
            Material::GgxConductor { reflectance, .. } => {
                let Some(m) = try_normalize(wo + wi) else {
                    return (Rgb::ZERO, 0.0);
                };
                // Both directions are above the horizon, so wo.m = wi.m > 0 and m.z > 0.
                // Visible normals, times the reflection Jacobian 1 / (4 wo.m):
                // G1(wo) (wo.m) D / cos_o / (4 wo.m) = D G1(wo) / (4 cos_o).
                let pdf = self.ggx.d(m) * self.pdf_scale;
                // f cos_i = R D G1(wi) G1(wo) / (4 cos_o) = R G1(wi) pdf.
                let f = reflectance * (pdf * self.ggx.g1(wi));
                (f, pdf)
            }
        }
    }

    /// f(wo, wi) cos(theta_i).
    #[inline]
    pub fn eval(&self, wi: Vec3) -> Rgb {
        self.eval_pdf(wi).0
    }

    /// Pdf per unit solid angle with which [`Material::sample`] draws `wi`.
    #[inline]
    pub fn pdf(&self, wi: Vec3) -> f32 {
        self.eval_pdf(wi).1
    }

    /// Draws `wi`: cosine-weighted (Lambertian) or visible normals (GGX). `None` when the draw
    /// leaves the upper hemisphere or `wo` is below it.
    #[inline]
    pub fn sample(&self, u: Vec2) -> Option<BsdfSample> {
        let wo = self.wo;
        if wo.z <= 0.0 {
            return None;
        }
        match self.material {
            Material::Lambertian { albedo } => {
                let wi = sample_cosine_hemisphere(u);
                let pdf = cosine_hemisphere_pdf(wi.z);
                // f cos / pdf = albedo exactly: the furnace has zero variance.
                (pdf > 0.0).then_some(BsdfSample { wi, weight: albedo, pdf })
            }
            Material::GgxConductor { alpha, reflectance } => {
                let m = sample_ggx_vndf(wo, alpha, u);
                let wo_m = dot(wo, m);
                if wo_m <= 0.0 {
                    return None;
                }
                let wi = m * (2.0 * wo_m) - wo;
                if wi.z <= 0.0 {
                    return None;
                }
                // The same expression as `eval_pdf`, so both techniques' weights see equal pdfs.
                let pdf = self.ggx.d(m) * self.pdf_scale;
                if !positive_finite(pdf) {
                    return None;
                }
                // f cos / pdf = R G1(wi) for visible-normal sampling.
                Some(BsdfSample { wi, weight: reflectance * self.ggx.g1(wi), pdf })
            }
        }
    }
}

impl Image for Material {
    fn put(&self, out: &mut dyn FnMut(u32)) {
        match *self {
            Material::Lambertian { albedo } => {
                out(0);
                albedo.put(out);
            }
            Material::GgxConductor { alpha, reflectance } => {
                out(1);
                alpha.put(out);
                reflectance.put(out);
            }
        }
    }
    fn get(w: &mut Words<'_>) -> Option<Self> {
        Some(match w.u32()? {
            0 => Material::Lambertian { albedo: vec3(&w.take::<3>()?, 0) },
            1 => {
                let a: [u32; 4] = w.take()?;
                Material::GgxConductor { alpha: float(&a, 0), reflectance: vec3(&a, 1) }
            }
            _ => return None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn construction_rejects_bad_values() {
        assert_eq!(Material::lambertian(Rgb::new(0.5, 1.5, 0.0)), Err(SceneError::OutOfRange(Field::Albedo)));
        assert_eq!(Material::ggx_conductor(0.0, Rgb::ONE), Err(SceneError::OutOfRange(Field::Alpha)));
        assert_eq!(Material::ggx_conductor(f32::NAN, Rgb::ONE), Err(SceneError::NonFinite(Field::Alpha)));
    }

    #[test]
    fn sample_weight_matches_eval_over_pdf() {
        let wo = Vec3::new(0.3, -0.2, 0.8).normalize();
        for m in [
            Material::lambertian(Rgb::splat(0.5)).unwrap(),
            Material::ggx_conductor(0.2, Rgb::splat(0.9)).unwrap(),
            Material::ggx_conductor(1e-3, Rgb::ONE).unwrap(),
        ] {
            for i in 0..16 {
                let u = Vec2::new((i as f32 + 0.5) / 16.0, ((i * 7) % 16) as f32 / 16.0 + 0.01);
                let Some(s) = m.sample(wo, u) else { continue };
                let expect = m.eval(wo, s.wi) / s.pdf;
                let rel = ((s.weight - expect).abs() / expect.max(Vec3::splat(1e-6))).max_element();
                assert!(rel < 2e-3, "{m:?} {s:?} {expect}");
                assert!((m.pdf(wo, s.wi) / s.pdf - 1.0).abs() < 2e-3);
            }
        }
    }

    #[test]
    fn one_sided() {
        let m = Material::lambertian(Rgb::ONE).unwrap();
        let below = Vec3::new(0.0, 0.0, -1.0);
        assert_eq!(m.eval(Vec3::Z, below), Rgb::ZERO);
        assert_eq!(m.eval(below, Vec3::Z), Rgb::ZERO);
        assert_eq!(m.pdf(below, Vec3::Z), 0.0);
        assert!(m.sample(below, Vec2::splat(0.5)).is_none());
    }
}
