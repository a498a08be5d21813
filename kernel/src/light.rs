//! Lights and light sampling: area emitters on shapes (constant radiance, front side only) and
//! point lights. `Light::sample_li` and `Light::pdf_li` are the pair the MIS weights rely on:
//! the pdf of a direction is evaluated by the same routine that the sampler's pdf comes from.

use crate::math::{Frame, PI, Rgb, Vec2, Vec3, luminance, max0, safe_sqrt, sqrt};
use crate::sampling::{
    SphericalRectangle, cone_one_minus_cos, sample_spherical_rectangle, sample_uniform_cone,
    spherical_rectangle, spherical_rectangle_pdf, uniform_cone_pdf,
};
use crate::shape::{Rectangle, Shape, SurfacePoint};

/// How points on sphere lights are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SphereSampling {
    /// Uniformly by area, converted to solid angle (the seed's formulation); about half the
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
    /// Proportional to emitted power (luminance).
    Power,
}

/// The closed set of lights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Constant radiance on the front side of a scene shape.
    Area {
        /// Index of the emitting shape in the scene.
        shape: u16,
        /// Emitted radiance.
        radiance: Rgb,
    },
    /// A point light (a delta light: only light sampling can find it).
    Point {
        /// Position.
        position: Vec3,
        /// Radiant intensity (W/sr per channel).
        intensity: Rgb,
    },
}

/// A sample drawn by light sampling, seen from the shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the shading point to the light (world).
    pub wi: Vec3,
    /// Distance to the sampled point.
    pub distance: f32,
    /// Incident radiance (for a point light: intensity / distance^2).
    pub radiance: Rgb,
    /// Pdf per unit solid angle, not including light selection (1 for a delta light).
    pub pdf: f32,
    /// True for a delta light: it has no pdf in solid angle and always gets weight one.
    pub delta: bool,
}

impl Light {
    /// Emitted power (luminance) used for light selection by power.
    pub fn power(&self, shape: Option<&Shape>) -> f32 {
        match *self {
            Light::Area { radiance, .. } => shape.map_or(0.0, |s| PI * max0(luminance(radiance)) * s.area()),
            Light::Point { intensity, .. } => 4.0 * PI * max0(luminance(intensity)),
        }
    }

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
        quads: QuadSampling,
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
                })
            }
            Light::Area { radiance, .. } => {
                let shape = shape?;
                if let (SphereSampling::Cone, Some((center, r))) = (spheres, shape.as_sphere()) {
                    if let Some(s) = sample_sphere_cone(center, r, x, u) {
                        return Some(LightSample { radiance, ..s });
                    }
                }
                if let Some((rect, sr)) = rectangle_seen_from(shape, x, quads) {
                    // Decided by the setup alone, as in `pdf_li`: no fallback after this point.
                    let local = sample_spherical_rectangle(&sr, u)?;
                    let distance = sqrt(local.length_squared());
                    let wi = (rect.ex * local.x + rect.ey * local.y + rect.n * local.z) / distance;
                    let pdf = spherical_rectangle_pdf(&sr);
                    return (distance > 0.0 && pdf.is_finite()).then_some(LightSample {
                        wi,
                        distance,
                        radiance,
                        pdf,
                        delta: false,
                    });
                }
                // Uniform area, converted to solid angle: p_w = p_A |x - y|^2 / cos(theta_y).
                let y = shape.sample_area(u);
                let pdf = area_to_solid_angle(shape.area_pdf(), x, &y)?;
                let v = y.p - x;
                let distance = sqrt(v.length_squared());
                Some(LightSample { wi: v / distance, distance, radiance, pdf, delta: false })
            }
        }
    }

    /// Pdf per unit solid angle with which [`Light::sample_li`] produces the direction from `x`
    /// to the point `y` of this light's shape (found by a BSDF ray); 0 for point lights.
    #[inline]
    pub fn pdf_li(
        &self,
        shape: Option<&Shape>,
        x: Vec3,
        y: &SurfacePoint,
        spheres: SphereSampling,
        quads: QuadSampling,
    ) -> f32 {
        match (self, shape) {
            (Light::Point { .. }, _) | (Light::Area { .. }, None) => 0.0,
            (Light::Area { .. }, Some(shape)) => {
                if let (SphereSampling::Cone, Some((center, r))) = (spheres, shape.as_sphere()) {
                    if let Some(omc) = sphere_cone(center, r, x) {
                        return uniform_cone_pdf(omc);
                    }
                }
                if let Some((_, sr)) = rectangle_seen_from(shape, x, quads) {
                    return spherical_rectangle_pdf(&sr);
                }
                area_to_solid_angle(shape.area_pdf(), x, y).unwrap_or(0.0)
            }
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
    })
}
