//! The light sampler: light sampling's one home. It chooses a light for a light sample
//! ([`LightSelection`]: uniformly or by power) and draws a direction to a point on it (sphere
//! lights by area or in the cone they subtend, [`SphereSampling`]), and it evaluates the
//! probabilities of what it drew, as pairs:
//!
//! - [`LightSampler::select`] / [`LightSampler::pmf`]: the light and its selection probability
//!   P(light), given the shading point (future strategies may weigh lights by their estimated
//!   contribution there; uniform and power selection do not look at it);
//! - [`LightSampler::sample`] / [`LightSampler::pdf`]: the light sample and its pdf per unit solid
//!   angle at `x`, p_w(wi | light), selection not included ([`LightSample::pdf`]).
//!
//! The light technique's pdf is their product, p_l = P(light) p_w, and the estimator writes it so.

use crate::ids::{LightId, ShapeId};
use crate::light::Light;
use crate::math::{Frame, Rgb, Vec2, Vec3, max0, safe_sqrt, sqrt};
use crate::sampling::{
    SphericalRectangle, cone_one_minus_cos, sample_spherical_rectangle, sample_uniform_cone,
    spherical_rectangle, spherical_rectangle_pdf, uniform_cone_pdf,
};
use crate::scene::Scene;
use crate::shape::Rectangle;
use crate::shape::{Shape, SurfacePoint};

/// How points on sphere lights are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SphereSampling {
    /// Uniformly by area, converted to solid angle (the lecture's formulation); about half the
    /// points lie on the far side and contribute nothing.
    Area,
    /// Uniformly inside the cone the sphere subtends (falls back to area from inside).
    #[default]
    Cone,
}

/// How points on quad lights are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum QuadSampling {
    /// Uniformly by area, converted to solid angle.
    #[default]
    Area,
    /// Uniformly in the solid angle the quad subtends (spherical rectangles, Ureña et al. 2013);
    /// by area for quads that are not rectangles and where f32 cannot resolve the solid angle
    /// (tiny or grazing rectangles, see [`spherical_rectangle`]).
    SolidAngle,
}

/// How a light is chosen when a scene has several.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LightSelection {
    /// Every light equally likely.
    #[default]
    Uniform,
    /// Proportional to emitted power (luminance), on the grid of the random number (see
    /// [`GridDistribution`](crate::sampling::GridDistribution)): every light that emits is
    /// chosen with exactly the probability the weights are given.
    Power,
}

/// The point light is sampled for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingPoint {
    /// Position.
    pub p: Vec3,
    /// Unit geometric normal of the front side.
    pub n: Vec3,
    /// Unit direction towards the viewer (world).
    pub wo: Vec3,
}

/// A light chosen for a light sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightChoice {
    /// The light.
    pub light: LightId,
    /// The probability with which it was chosen, P(light).
    pub probability: f32,
}

/// A sample drawn on a chosen light, seen from the shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the shading point to the light (world).
    pub wi: Vec3,
    /// Distance to the sampled point.
    pub distance: f32,
    /// Incident radiance (for a point light: intensity / distance^2).
    pub radiance: Rgb,
    /// Pdf per unit solid angle of `wi` given the light, p_w(wi | light); 1 for a delta light.
    /// Never includes the light's selection probability.
    pub pdf: f32,
    /// True for a delta light: it has no pdf in solid angle and always gets weight one.
    pub delta: bool,
    /// The shape the point lies on (area lights): the shadow ray may end on it.
    pub emitter: Option<ShapeId>,
}

/// Light sampling in one scene with one strategy for each choice.
#[derive(Clone, Copy, Debug)]
pub struct LightSampler<'a, const S: usize, const L: usize, const M: usize> {
    scene: &'a Scene<S, L, M>,
    selection: LightSelection,
    spheres: SphereSampling,
    quads: QuadSampling,
}

impl<'a, const S: usize, const L: usize, const M: usize> LightSampler<'a, S, L, M> {
    /// The sampler of `scene`'s lights choosing by `selection`, drawing on spheres by `spheres`
    /// (and on quads by area, see [`LightSampler::with_quad_sampling`]).
    #[inline]
    pub fn new(scene: &'a Scene<S, L, M>, selection: LightSelection, spheres: SphereSampling) -> Self {
        Self { scene, selection, spheres, quads: QuadSampling::Area }
    }

    /// The same sampler drawing on quads by `quads`.
    #[inline]
    pub fn with_quad_sampling(mut self, quads: QuadSampling) -> Self {
        self.quads = quads;
        self
    }

    /// Chooses a light with the random number `u`; `None` when the scene has no light.
    #[inline]
    pub fn select(&self, _at: &ShadingPoint, u: f32) -> Option<LightChoice> {
        let n = self.scene.lights().len();
        if n == 0 {
            return None;
        }
        if let LightSelection::Power = self.selection {
            if let Some((i, probability)) = self.scene.light_powers().sample(u) {
                return Some(LightChoice { light: LightId::new(i as u16), probability });
            }
        }
        // Uniform (also when no light has power).
        let i = ((u * n as f32) as usize).min(n - 1);
        Some(LightChoice { light: LightId::new(i as u16), probability: 1.0 / n as f32 })
    }

    /// The probability with which [`LightSampler::select`] chooses `light` at `at`.
    #[inline]
    pub fn pmf(&self, _at: &ShadingPoint, light: LightId) -> f32 {
        let n = self.scene.lights().len();
        if light.index() >= n {
            return 0.0;
        }
        let powers = self.scene.light_powers();
        match self.selection {
            LightSelection::Power if !powers.is_empty() => powers.pmf(light.index()),
            _ => 1.0 / n as f32,
        }
    }

    /// Draws a point on `light` as seen from `x` with the random numbers `u`; `None` when the
    /// sample carries no light (see [`Light::sample_li`]) or the scene has no such light.
    #[inline]
    pub fn sample(&self, light: LightId, x: Vec3, u: Vec2) -> Option<LightSample> {
        let light = self.scene.light(light)?;
        let shape = self.scene.light_shape(light);
        if let (Light::Area { radiance, shape: emitter }, Some(shape)) = (light, shape) {
            if let Some((rect, sr)) = rectangle_seen_from(shape, x, self.quads) {
                // Decided by the setup alone, as in `pdf`: no fallback after this point.
                let local = sample_spherical_rectangle(&sr, u)?;
                let distance = sqrt(local.length_squared());
                let wi = (rect.ex * local.x + rect.ey * local.y + rect.n * local.z) / distance;
                let pdf = spherical_rectangle_pdf(&sr);
                return (distance > 0.0 && pdf.is_finite()).then_some(LightSample {
                    wi,
                    distance,
                    radiance: *radiance,
                    pdf,
                    delta: false,
                    emitter: Some(*emitter),
                });
            }
        }
        light.sample_li(shape, x, u, self.spheres)
    }

    /// Pdf per unit solid angle at `x` with which [`LightSampler::sample`] draws the direction to
    /// the point `y` of `light` (found by a BSDF ray), selection not included; 0 for point lights.
    #[inline]
    pub fn pdf(&self, light: LightId, x: Vec3, y: &SurfacePoint) -> f32 {
        match self.scene.light(light) {
            Some(light) => {
                let shape = self.scene.light_shape(light);
                if let (Light::Area { .. }, Some((_, sr))) =
                    (light, shape.and_then(|s| rectangle_seen_from(s, x, self.quads)))
                {
                    return spherical_rectangle_pdf(&sr);
                }
                light.pdf_li(shape, x, y, self.spheres)
            }
            None => 0.0,
        }
    }
}

/// The spherical rectangle a rectangular quad light subtends at `x`, when quads are sampled in
/// solid angle and f32 can resolve it (else the light is sampled by area).
#[inline]
fn rectangle_seen_from(
    shape: &Shape,
    x: Vec3,
    quads: QuadSampling,
) -> Option<(Rectangle, SphericalRectangle)> {
    if quads != QuadSampling::SolidAngle {
        return None;
    }
    let rect = shape.as_rectangle()?;
    let d = rect.p0 - x;
    let corner = Vec3::new(d.dot(rect.ex), d.dot(rect.ey), d.dot(rect.n));
    Some((rect, spherical_rectangle(corner, rect.lengths.x, rect.lengths.y)?))
}

impl Light {
    /// Draws a point on the light as seen from `x`. `shape` is the emitting shape of an area
    /// light (ignored for point lights). `None` when the sample carries no light (a point on the
    /// far side of a sphere, behind a quad, or a point light at `x`).
    #[inline]
    pub fn sample_li(
        &self,
        shape: Option<&Shape>,
        x: Vec3,
        u: Vec2,
        spheres: SphereSampling,
    ) -> Option<LightSample> {
        match *self {
            Light::Point { position, intensity } => {
                let v = position - x;
                let d2 = v.length_squared();
                if !(d2 > 0.0) {
                    return None;
                }
                let distance = sqrt(d2);
                Some(LightSample {
                    wi: v / distance,
                    distance,
                    radiance: intensity / d2,
                    pdf: 1.0,
                    delta: true,
                    emitter: None,
                })
            }
            Light::Area { radiance, shape: emitter } => {
                let shape = shape?;
                let emitter = Some(emitter);
                if let (SphereSampling::Cone, Some((center, r))) = (spheres, shape.as_sphere()) {
                    if let Some(s) = sample_sphere_cone(center, r, x, u) {
                        return Some(LightSample { radiance, emitter, ..s });
                    }
                }
                // Uniform area, converted to solid angle: p_w = p_A |x - y|^2 / cos(theta_y).
                let y = shape.sample_area(u);
                let pdf = area_to_solid_angle(shape.area_pdf(), x, &y)?;
                let v = y.p - x;
                let distance = sqrt(v.length_squared());
                Some(LightSample { wi: v / distance, distance, radiance, pdf, delta: false, emitter })
            }
        }
    }

    /// Pdf per unit solid angle with which [`Light::sample_li`] produces the direction from `x`
    /// to the point `y` of this light's shape (found by a BSDF ray); 0 for point lights.
    #[inline]
    pub fn pdf_li(&self, shape: Option<&Shape>, x: Vec3, y: &SurfacePoint, spheres: SphereSampling) -> f32 {
        match (self, shape) {
            (Light::Point { .. }, _) | (Light::Area { .. }, None) => 0.0,
            (Light::Area { .. }, Some(shape)) => {
                if let (SphereSampling::Cone, Some((center, r))) = (spheres, shape.as_sphere()) {
                    if let Some(omc) = sphere_cone(center, r, x) {
                        return uniform_cone_pdf(omc);
                    }
                }
                area_to_solid_angle(shape.area_pdf(), x, y).unwrap_or(0.0)
            }
        }
    }
}

/// Converts an area pdf at `y` to solid angle at `x`; `None` where `y` faces away from `x`.
#[inline]
fn area_to_solid_angle(pdf_area: f32, x: Vec3, y: &SurfacePoint) -> Option<f32> {
    let v = x - y.p;
    let d2 = v.length_squared();
    let cos_y = y.n.dot(v);
    // cos_y here is unnormalized (times |v|): pdf = p_A d^2 / (cos_y / d) = p_A d^3 / cos_y'.
    if !(cos_y > 0.0) || !(d2 > 0.0) {
        return None;
    }
    let pdf = pdf_area * d2 * sqrt(d2) / cos_y;
    pdf.is_finite().then_some(pdf)
}

/// `1 - cos(theta_max)` of the cone a sphere subtends from `x`; `None` from inside or on it.
#[inline]
fn sphere_cone(center: Vec3, radius: f32, x: Vec3) -> Option<f32> {
    let d2 = (center - x).length_squared();
    let r2 = radius * radius;
    (d2 > r2).then(|| cone_one_minus_cos(r2 / d2))
}

/// Uniform direction in the cone a sphere subtends, and the near point it hits.
#[inline]
fn sample_sphere_cone(center: Vec3, radius: f32, x: Vec3, u: Vec2) -> Option<LightSample> {
    let omc = sphere_cone(center, radius, x)?;
    let to_c = center - x;
    let d2 = to_c.length_squared();
    let d = sqrt(d2);
    let frame = Frame::from_normal(to_c / d);
    let local = sample_uniform_cone(u, omc);
    let wi = frame.to_world(local);
    // Distance to the near intersection: d cos(theta) - sqrt(r^2 - d^2 sin^2(theta)).
    let sin2 = local.x * local.x + local.y * local.y;
    let distance = max0(d * local.z - safe_sqrt(radius * radius - d2 * sin2));
    let pdf = uniform_cone_pdf(omc);
    (pdf > 0.0 && pdf.is_finite()).then_some(LightSample {
        wi,
        distance,
        radiance: Rgb::ZERO,
        pdf,
        delta: false,
        emitter: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{Film, test_desc};
    use crate::material::Material;

    fn scene() -> Scene<2, 3, 1> {
        let cam = test_desc(40.0);
        let mut s: Scene<2, 3, 1> = Scene::new(cam, Film::new(4, 4).unwrap()).unwrap();
        let m = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
        let a = s.add_shape(Shape::sphere(Vec3::ZERO, 1.0).unwrap(), m).unwrap();
        s.add_area_light(a, Rgb::splat(2.0)).unwrap();
        s.add_point_light(Vec3::ONE, Rgb::splat(1.0)).unwrap();
        s.add_point_light(Vec3::ONE, Rgb::ZERO).unwrap();
        s
    }

    #[test]
    fn selection_probabilities_sum_to_one_and_are_realised() {
        let s = scene();
        let at = ShadingPoint { p: Vec3::new(0.0, 3.0, 0.0), n: Vec3::Y, wo: Vec3::Y };
        for sel in [LightSelection::Uniform, LightSelection::Power] {
            let lights = LightSampler::new(&s, sel, SphereSampling::Cone);
            let sum: f32 = (0..3).map(|i| lights.pmf(&at, LightId::new(i))).sum();
            assert!((sum - 1.0).abs() < 1e-6);
            assert_eq!(lights.pmf(&at, LightId::new(3)), 0.0);
            // Never selects a light with zero selection probability.
            for k in 0..1000 {
                let c = lights.select(&at, k as f32 / 1000.0).unwrap();
                assert!(c.probability > 0.0 && c.probability == lights.pmf(&at, c.light));
            }
        }
    }

    #[test]
    fn samples_name_their_emitter_and_exclude_selection() {
        let s = scene();
        let lights = LightSampler::new(&s, LightSelection::Power, SphereSampling::Cone);
        let x = Vec3::new(0.0, 3.0, 0.0);
        let ls = lights.sample(LightId::new(0), x, Vec2::new(0.3, 0.6)).unwrap();
        assert_eq!(ls.emitter, Some(ShapeId::new(0)));
        let y = SurfacePoint { p: x + ls.wi * ls.distance, n: (x + ls.wi * ls.distance).normalize() };
        assert_eq!(lights.pdf(LightId::new(0), x, &y), ls.pdf);
        let point = lights.sample(LightId::new(1), x, Vec2::new(0.3, 0.6)).unwrap();
        assert!(point.delta && point.emitter.is_none() && point.pdf == 1.0);
        assert!(lights.sample(LightId::new(9), x, Vec2::ZERO).is_none());
        assert_eq!(lights.pdf(LightId::new(9), x, &y), 0.0);
    }
}
