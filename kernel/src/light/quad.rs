//! How points on quad lights are drawn: a strategy type per way ([`QuadSampler`]).

use crate::geometry::{Ray, Rectangle, Shape};
use crate::light::sample::{LightSample, ShadingPoint};
use crate::num::{Vec2, Vec3, sqrt};
use crate::sampling::{
    SphericalRectangle, bilinear_pdf, fitted_cosine_warp, invert_spherical_rectangle_sample, sample_bilinear,
    sample_spherical_rectangle, spherical_rectangle, spherical_rectangle_cosines, spherical_rectangle_pdf,
};
use crate::scene::Material;

crate::choices! {
    /// How points on quad lights are drawn.
    pub enum QuadSampling: "quad sampling" {
        /// Uniformly by area, converted to solid angle ([`ByArea`]).
        Area = "area", "uniformly by area";
        /// Uniformly in the solid angle the quad subtends ([`SolidAngle`]).
        SolidAngle = "solid-angle", "uniformly in solid angle (spherical rectangles; by area where unstable)";
        /// In solid angle, warped by the receiver's cosine ([`SolidAngleCosine`]).
        SolidAngleCosine = "solid-angle-cosine", "in solid angle, warped by the receiver's cosine (Hart et al. 2020)";
        /// In solid angle, warped by the cosine where the receiver does not face the quad ([`Adaptive`]).
        Auto = "auto", "in solid angle, warped by the receiver's cosine where the warp fits it";
        /// By area, but in solid angle where a Lambertian receiver's normal meets a quad that does not look small and steep, and as `auto` for sharp GGX ([`BySize`]).
        BySize = "by-size", "by area, but in solid angle where a Lambertian receiver's normal meets a quad that does not look small and steep, and as auto for GGX sharper than alpha 0.25 (measured best)";
    }
}

/// A way of drawing points on quad lights. Where a quad is not sampled this way
/// ([`QuadSampler::seen`] is `None`), it is sampled uniformly by area, like any shape.
pub trait QuadSampler: Sync + 'static {
    /// Its name among the settings.
    const KIND: QuadSampling;
    /// Whether the scene may have quad lights: false for [`Absent`] (a firmware's scene file has
    /// none), and the code of the other strategies for quad lights is left out.
    const PRESENT: bool = true;

    /// The quad `shape` seen from the receiver `at`, where this strategy samples it: decided by the setup
    /// alone, so that a sample and the pdf of any direction take the same way. By default the
    /// spherical rectangle of a rectangular quad, where f32 can resolve it.
    #[inline]
    fn seen(shape: &Shape, at: &ShadingPoint) -> Option<(Rectangle, SphericalRectangle)> {
        rectangle_in_solid_angle(shape, at.p)
    }

    /// A direction to the rectangle `rect` (seen as `sr`) from the shading point `at`; radiance
    /// and emitter are left for the caller.
    fn sample(rect: &Rectangle, sr: &SphericalRectangle, at: &ShadingPoint, u: Vec2) -> Option<LightSample>;

    /// The pdf with which [`QuadSampler::sample`] reaches the point `y` of the rectangle from
    /// the shading point `at`.
    fn pdf(rect: &Rectangle, sr: &SphericalRectangle, at: &ShadingPoint, y: Vec3) -> f32;
}

/// Quad lights by area, like any shape.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ByArea;

impl QuadSampler for ByArea {
    const KIND: QuadSampling = QuadSampling::Area;

    #[inline(always)]
    fn seen(_: &Shape, _: &ShadingPoint) -> Option<(Rectangle, SphericalRectangle)> {
        None
    }

    #[inline(always)]
    fn sample(_: &Rectangle, _: &SphericalRectangle, _: &ShadingPoint, _: Vec2) -> Option<LightSample> {
        None
    }

    #[inline(always)]
    fn pdf(_: &Rectangle, _: &SphericalRectangle, _: &ShadingPoint, _: Vec3) -> f32 {
        0.0
    }
}

/// No quad lights in the scene (a build script names it for a scene file that has none): any
/// quad light is sampled by area, and the other strategies leave out their code for quad
/// lights (lobe mixing and the control variate skip them: still unbiased, as without them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Absent;

impl QuadSampler for Absent {
    const KIND: QuadSampling = QuadSampling::Area;
    const PRESENT: bool = false;

    #[inline(always)]
    fn seen(_: &Shape, _: &ShadingPoint) -> Option<(Rectangle, SphericalRectangle)> {
        None
    }

    #[inline(always)]
    fn sample(_: &Rectangle, _: &SphericalRectangle, _: &ShadingPoint, _: Vec2) -> Option<LightSample> {
        None
    }

    #[inline(always)]
    fn pdf(_: &Rectangle, _: &SphericalRectangle, _: &ShadingPoint, _: Vec3) -> f32 {
        0.0
    }
}

/// Rectangular quad lights uniformly in the solid angle they subtend (spherical rectangles,
/// Ureña et al. 2013); by area for quads that are not rectangles and where f32 cannot resolve
/// the solid angle (tiny or grazing rectangles, see [`spherical_rectangle`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SolidAngle;

impl QuadSampler for SolidAngle {
    const KIND: QuadSampling = QuadSampling::SolidAngle;

    #[inline]
    fn sample(rect: &Rectangle, sr: &SphericalRectangle, _: &ShadingPoint, u: Vec2) -> Option<LightSample> {
        toward_rectangle(rect, sr, u, None)
    }

    #[inline]
    fn pdf(_: &Rectangle, sr: &SphericalRectangle, _: &ShadingPoint, _: Vec3) -> f32 {
        spherical_rectangle_pdf(sr)
    }
}

/// As [`SolidAngle`], with the 2-D sample first warped towards the receiver's cosine (Hart et
/// al. 2020, as pbrt-v4 does for rectangles): a bilinear density whose corner values are the
/// cosines towards the rectangle's corners ([`spherical_rectangle_cosines`]); the pdf is the
/// spherical rectangle's times the bilinear one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SolidAngleCosine;

impl QuadSampler for SolidAngleCosine {
    const KIND: QuadSampling = QuadSampling::SolidAngleCosine;

    #[inline]
    fn sample(rect: &Rectangle, sr: &SphericalRectangle, at: &ShadingPoint, u: Vec2) -> Option<LightSample> {
        sample_warped(rect, sr, cosine_weights(rect, sr, at.n), u)
    }

    #[inline]
    fn pdf(rect: &Rectangle, sr: &SphericalRectangle, at: &ShadingPoint, y: Vec3) -> f32 {
        warped_pdf(rect, sr, cosine_weights(rect, sr, at.n), at, y)
    }
}

/// [`SolidAngleCosine`] where the bilinear warp fits the receiver's cosine, [`SolidAngle`] where
/// it does not ([`fitted_cosine_warp`]: the cosine peaks inside the quad or along an edge, as on a
/// floor under a large, close ceiling light or beside the foot of a wall light, and the corners
/// understate it). Decided per shading point by the rectangle and the normal alone, the same way
/// in `sample` and `pdf`. Measured (docs/defaults.md): the lowest error of the three on
/// glossy_lights, low_ceiling and stress, where each of the others loses 6-7 % on one of them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Adaptive;

impl QuadSampler for Adaptive {
    const KIND: QuadSampling = QuadSampling::Auto;

    #[inline]
    fn sample(rect: &Rectangle, sr: &SphericalRectangle, at: &ShadingPoint, u: Vec2) -> Option<LightSample> {
        match fitted_cosine_warp(sr, to_local(rect, at.n)) {
            Some(w) => sample_warped(rect, sr, w, u),
            None => SolidAngle::sample(rect, sr, at, u),
        }
    }

    #[inline]
    fn pdf(rect: &Rectangle, sr: &SphericalRectangle, at: &ShadingPoint, y: Vec3) -> f32 {
        match fitted_cosine_warp(sr, to_local(rect, at.n)) {
            Some(w) => warped_pdf(rect, sr, w, at, y),
            None => SolidAngle::pdf(rect, sr, at, y),
        }
    }
}

/// The spherical rectangle only where it pays, by area elsewhere ([`BySize::by_area`]). A
/// Lambertian receiver draws the rectangle uniformly in solid angle where its normal meets it
/// and it does not look small and steep: there the cosine peaks inside the rectangle (a floor
/// under a large, close ceiling light), the solid angle follows the integrand, and the cosine
/// warp's corners would understate the peak. Elsewhere by area: where the rectangle looks small
/// and steep ([`Shape::looks_small_and_steep`] with [`BySize::SMALL`]) the distance and both
/// cosines hardly vary over it, and where the normal misses it the cosine is largest at its
/// near edge, as the area's pdf in solid angle is (measured, docs/defaults.md: on box_quad and
/// diffuse_room the cosine-warped rectangle there bought 0.5-1 % less error for 12-14 % more
/// time).
/// A rough GGX receiver ([`BySize::ROUGH`]) draws by area too: its lobe follows neither the
/// solid angle nor the cosine. Sharper GGX receivers take [`Adaptive`]'s way: where their lobe
/// meets a large quad at a grazing angle (stress's floor), light samples still matter. Decided
/// by the receiver alone, the same way in `sample` and `pdf`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BySize;

impl BySize {
    /// The ratio of heights to diagonal from which a rectangle is drawn by area
    /// ([`Shape::looks_small_and_steep`]). Measured before the normal's test (docs/defaults.md,
    /// 1, 1.5, 2 and 3): at 1.5 the error on glossy_lights stays within 4 % of `auto`'s (its wall
    /// sees a tilted panel at a grazing angle), while on box_quad and diffuse_room the time falls
    /// by a third.
    pub const SMALL: f32 = 1.5;

    /// The GGX alpha from which a receiver draws quads by area. Measured (docs/defaults.md):
    /// on glossy_lights (alpha 0.3 to 0.8) by area has 0.97x the error at about 0.8x the time;
    /// on stress, by area on its alpha = 0.001 floor has 1.04x the error. No scene measured has
    /// quad lights and an alpha between 0.05 and 0.3; 0.25 keeps every measured near mirror
    /// (mirror_lights: 0.004 to 0.05) and the lecture's plates (to 0.1) well below it.
    pub const ROUGH: f32 = 0.25;

    /// Whether a receiver of material `m` may draw quads by area: a Lambertian one (see
    /// [`BySize::by_area`]) or a rough GGX one. Without such a receiver this strategy is
    /// [`Adaptive`] (a firmware's build script names that then).
    #[inline]
    pub fn by_area_for(m: &Material) -> bool {
        match *m {
            Material::Lambertian { .. } => true,
            Material::GgxConductor { alpha, .. } => alpha >= Self::ROUGH,
        }
    }

    /// Whether the receiver `at` draws the quad `shape` by area: a Lambertian one where the quad
    /// looks small and steep or where its normal (a ray from its point) does not meet the quad, a
    /// rough GGX one always.
    #[inline]
    pub fn by_area(shape: &Shape, at: &ShadingPoint) -> bool {
        match at.bsdf {
            Material::Lambertian { .. } => {
                shape.looks_small_and_steep(at.p, at.n, Self::SMALL) || !normal_meets(shape, at)
            }
            Material::GgxConductor { .. } => Self::by_area_for(&at.bsdf),
        }
    }
}

impl QuadSampler for BySize {
    const KIND: QuadSampling = QuadSampling::BySize;

    /// Nothing for spheres (before the rule's tests, which would cost a sphere light's every sample).
    #[inline]
    fn seen(shape: &Shape, at: &ShadingPoint) -> Option<(Rectangle, SphericalRectangle)> {
        if !matches!(shape, Shape::Quad(_)) || Self::by_area(shape, at) {
            return None;
        }
        rectangle_in_solid_angle(shape, at.p)
    }

    /// A Lambertian receiver uniformly in solid angle (where its normal meets the quad, the cosine
    /// peaks inside it, and the warp's corners would understate it); others as [`Adaptive`].
    #[inline]
    fn sample(rect: &Rectangle, sr: &SphericalRectangle, at: &ShadingPoint, u: Vec2) -> Option<LightSample> {
        if lambertian(at) { SolidAngle::sample(rect, sr, at, u) } else { Adaptive::sample(rect, sr, at, u) }
    }

    #[inline]
    fn pdf(rect: &Rectangle, sr: &SphericalRectangle, at: &ShadingPoint, y: Vec3) -> f32 {
        if lambertian(at) { SolidAngle::pdf(rect, sr, at, y) } else { Adaptive::pdf(rect, sr, at, y) }
    }
}

/// Whether the receiver's normal, from its point, meets the quad `shape` (its cosine then peaks
/// inside the quad).
#[inline]
fn normal_meets(shape: &Shape, at: &ShadingPoint) -> bool {
    shape.intersect(&Ray { origin: at.p, dir: at.n }, 0.0, f32::INFINITY).is_some()
}

/// Whether the receiver `at` is Lambertian.
#[inline]
fn lambertian(at: &ShadingPoint) -> bool {
    matches!(at.bsdf, Material::Lambertian { .. })
}

/// A direction to the rectangle drawn by the cosine warp with corner weights `w`.
#[inline]
fn sample_warped(rect: &Rectangle, sr: &SphericalRectangle, w: [f32; 4], u: Vec2) -> Option<LightSample> {
    let v = sample_bilinear(u, w);
    toward_rectangle(rect, sr, v, Some(bilinear_pdf(v, w)))
}

/// The pdf of [`sample_warped`] with corner weights `w` reaching `y` from `at`.
#[inline(never)]
fn warped_pdf(rect: &Rectangle, sr: &SphericalRectangle, w: [f32; 4], at: &ShadingPoint, y: Vec3) -> f32 {
    spherical_rectangle_pdf(sr)
        * bilinear_pdf(invert_spherical_rectangle_sample(sr, to_local(rect, y - at.p)), w)
}

/// A world vector in the rectangle's local frame (edges x, y; normal z).
#[inline]
fn to_local(rect: &Rectangle, v: Vec3) -> Vec3 {
    Vec3::new(v.dot(rect.ex), v.dot(rect.ey), v.dot(rect.n))
}

/// The spherical rectangle a rectangular quad subtends at `x`, where f32 can resolve it.
#[inline]
fn rectangle_in_solid_angle(shape: &Shape, x: Vec3) -> Option<(Rectangle, SphericalRectangle)> {
    let rect = shape.as_rectangle()?;
    Some((rect, spherical_rectangle(to_local(&rect, rect.p0 - x), rect.lengths.x, rect.lengths.y)?))
}

/// The corner weights of the cosine warp for a receiver with unit normal `n` (world).
#[inline]
fn cosine_weights(rect: &Rectangle, sr: &SphericalRectangle, n: Vec3) -> [f32; 4] {
    spherical_rectangle_cosines(sr, to_local(rect, n))
}

/// The direction to the rectangle `rect` (seen as `sr`) at the sample `u` of the spherical
/// rectangle, with its pdf in solid angle times the pdf `warp` of a warp of `u`, if any. Out of
/// line: one copy in the firmware.
#[inline(never)]
fn toward_rectangle(
    rect: &Rectangle,
    sr: &SphericalRectangle,
    u: Vec2,
    warp: Option<f32>,
) -> Option<LightSample> {
    let local = sample_spherical_rectangle(sr, u)?;
    let distance = sqrt(local.length_squared());
    let wi = (rect.ex * local.x + rect.ey * local.y + rect.n * local.z) / distance;
    let pdf = spherical_rectangle_pdf(sr);
    let pdf = match warp {
        Some(w) => pdf * w,
        None => pdf,
    };
    (distance > 0.0 && pdf.is_finite()).then_some(LightSample::towards(wi, distance, pdf))
}
