//! How points on sphere lights are drawn: a strategy type per way ([`SphereSampler`]).

use crate::light::sample::LightSample;
use crate::num::{Vec2, Vec3, dot, from_local_around, max0, positive_finite, safe_sqrt, sqrt};
use crate::sampling::{cone_one_minus_cos, sample_uniform_cone, uniform_cone_pdf};

crate::choices! {
    /// How points on sphere lights are drawn.
    pub enum SphereSampling: "sphere sampling" {
        /// Uniformly by area, converted to solid angle (the lecture's formulation); about half
        /// the points lie on the far side and contribute nothing ([`ByArea`]).
        Area = "area", "uniformly by area (the lecture's formulation)";
        /// Uniformly inside the cone the sphere subtends; by area from inside ([`InCone`]).
        Cone = "cone", "uniformly in the cone the sphere subtends";
    }
}

/// A way of drawing points on sphere lights. Where it has nothing to offer (`None`), the light
/// is sampled uniformly by area, like any shape.
pub trait SphereSampler: Sync + 'static {
    /// Its name among the settings.
    const KIND: SphereSampling;
    /// Whether the scene may have sphere lights: false for [`Absent`] (a firmware's scene file
    /// has none), and the code of the other strategies for sphere lights is left out.
    const PRESENT: bool = true;

    /// A direction from `x` to the sphere (`center`, `radius`) and its pdf, drawn with `u`;
    /// radiance and emitter are left for the caller. `None`: draw it by area instead.
    fn sample(center: Vec3, radius: f32, x: Vec3, u: Vec2) -> Option<LightSample>;

    /// The pdf per unit solid angle with which [`SphereSampler::sample`] reaches any point of
    /// the sphere from `x`; `None`: the area pdf applies.
    fn pdf(center: Vec3, radius: f32, x: Vec3) -> Option<f32>;
}

/// Sphere lights by area, like any shape (the lecture's formulation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ByArea;

impl SphereSampler for ByArea {
    const KIND: SphereSampling = SphereSampling::Area;

    #[inline(always)]
    fn sample(_: Vec3, _: f32, _: Vec3, _: Vec2) -> Option<LightSample> {
        None
    }

    #[inline(always)]
    fn pdf(_: Vec3, _: f32, _: Vec3) -> Option<f32> {
        None
    }
}

/// Sphere lights uniformly in the cone they subtend (by area from inside them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct InCone;

impl SphereSampler for InCone {
    const KIND: SphereSampling = SphereSampling::Cone;

    /// A uniform direction in the cone and the near point it hits.
    #[inline]
    fn sample(center: Vec3, radius: f32, x: Vec3, u: Vec2) -> Option<LightSample> {
        let omc = sphere_cone(center, radius, x)?;
        let to_c = center - x;
        let d2 = dot(to_c, to_c);
        let d = sqrt(d2);
        let local = sample_uniform_cone(u, omc);
        let wi = from_local_around(to_c * (1.0 / d), local);
        // Distance to the near intersection: d cos(theta) - sqrt(r^2 - d^2 sin^2(theta)).
        let sin2 = local.x * local.x + local.y * local.y;
        let distance = max0(d * local.z - safe_sqrt(radius * radius - d2 * sin2));
        let pdf = uniform_cone_pdf(omc);
        positive_finite(pdf).then_some(LightSample::towards(wi, distance, pdf))
    }

    #[inline]
    fn pdf(center: Vec3, radius: f32, x: Vec3) -> Option<f32> {
        sphere_cone(center, radius, x).map(uniform_cone_pdf)
    }
}

/// `1 - cos(theta_max)` of the cone a sphere subtends from `x`; `None` from inside or on it.
#[inline]
fn sphere_cone(center: Vec3, radius: f32, x: Vec3) -> Option<f32> {
    let to_center = center - x;
    let d2 = dot(to_center, to_center);
    let r2 = radius * radius;
    (d2 > r2).then(|| cone_one_minus_cos(r2 / d2))
}

/// No sphere lights in the scene (a build script names it for a scene file that has none): any
/// sphere light is sampled by area, and the other strategies leave out their code for sphere
/// lights (lobe mixing and the control variate skip them: still unbiased, as without them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Absent;

impl SphereSampler for Absent {
    const KIND: SphereSampling = SphereSampling::Area;
    const PRESENT: bool = false;

    #[inline(always)]
    fn sample(_: Vec3, _: f32, _: Vec3, _: Vec2) -> Option<LightSample> {
        None
    }

    #[inline(always)]
    fn pdf(_: Vec3, _: f32, _: Vec3) -> Option<f32> {
        None
    }
}
