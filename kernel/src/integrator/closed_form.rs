//! Closed forms of the light that reaches a Lambertian receiver when nothing is in the way: the
//! "analytic unoccluded light" of the control variate
//!
//! integral f V = integral f (closed form here) + integral f (V - 1) (sampled with MIS),
//!
//! which is unbiased and has no noise wherever a light is unoccluded. For a Lambertian receiver
//! of albedo rho, integral f = rho / pi L Omega_perp, with Omega_perp = integral max(0, cos
//! theta) dw over the directions in which the light shows its front side: the projected solid
//! angle, given here for quads (Lambert's polygon formula after clipping to the receiver's
//! horizon) and spheres (Snyder 1996, with the horizon). Where f32 cannot be trusted to resolve
//! it (tiny or far quads, spheres cut by the horizon at tiny angles, points on or in a sphere),
//! `None`: that light is then sampled as usual at that point. Every test is deterministic on f32
//! values, so the host and a Cortex-M choose alike.

use crate::geometry::Shape;
use crate::integrator::control_variate::ControlVariateStrategy;
use crate::light::quad::QuadSampler;
use crate::light::sphere::SphereSampler;
use crate::num::{INV_PI, PI, Rgb, Vec3, acos, atan2, clamp, safe_sqrt, sqrt};
use crate::scene::Light;
use crate::scene::Material;
use crate::scene::{Hit, LightId, Scene};

/// A closed form is trusted when its value is at least this fraction of the sum of the magnitudes
/// of its terms (at most ~1e-4 relative rounding error from cancellation, typically 1e-6).
pub const MIN_RELATIVE: f32 = 1e-3;

/// Projected solid angle of `shape`'s front side from `x` with unit normal `n` (see the module
/// docs); `None` where no closed form is trusted.
#[inline]
pub fn projected_solid_angle(shape: &Shape, x: Vec3, n: Vec3) -> Option<f32> {
    match shape.as_sphere() {
        Some((center, r)) => sphere_projected_solid_angle(center - x, r, n),
        None => shape.corners().and_then(|c| quad_projected_solid_angle(c.map(|v| v - x), n)),
    }
}

/// Projected solid angle of a one-sided convex quad with corners `v` (relative to the receiver,
/// in the order whose right-hand normal is the front side), clipped to the horizon of `n`.
#[inline]
pub fn quad_projected_solid_angle(v: [Vec3; 4], n: Vec3) -> Option<f32> {
    let [v0, v1, _, v3] = v;
    // The receiver sees the front side iff it lies on the side the normal points to.
    if !((v1 - v0).cross(v3 - v0).dot(-v0) > 0.0) {
        return Some(0.0);
    }
    // Clip to the upper half-space n . v >= 0 (Sutherland-Hodgman): at most 5 corners.
    let mut poly = [Vec3::ZERO; 5];
    let mut k = 0usize;
    for i in 0..4 {
        let (a, b) = (v[i], v[(i + 1) % 4]);
        let (ha, hb) = (n.dot(a), n.dot(b));
        if ha >= 0.0 {
            if let Some(slot) = poly.get_mut(k) {
                *slot = a;
                k += 1;
            }
        }
        if (ha >= 0.0) != (hb >= 0.0) {
            let t = ha / (ha - hb);
            if let Some(slot) = poly.get_mut(k) {
                *slot = a + (b - a) * t;
                k += 1;
            }
        }
    }
    if k < 3 {
        return Some(0.0);
    }
    // The corners' directions (each corner once: the same values for both its edges).
    for p in poly.iter_mut().take(k) {
        let l = p.length_squared();
        if !(l > 0.0) {
            return None;
        }
        *p /= sqrt(l);
    }
    let mut sum = 0.0f32;
    let mut magnitude = 0.0f32;
    for i in 0..k {
        let (a, b) = (*poly.get(i)?, *poly.get((i + 1) % k)?);
        let c = a.cross(b);
        let sin = sqrt(c.length_squared());
        if !(sin > 0.0) {
            continue; // a clipped corner repeated: no edge
        }
        // The edge's angle, 2 atan2(|a - b|, |a + b|), accurate at every size.
        let angle = 2.0 * atan2(sqrt((a - b).length_squared()), sqrt((a + b).length_squared()));
        let term = angle / sin * n.dot(c);
        sum += term;
        magnitude += term.abs();
    }
    let value = 0.5 * sum.abs();
    (value.is_finite() && (value == 0.0 || 2.0 * value >= MIN_RELATIVE * magnitude)).then_some(value)
}

/// Projected solid angle of a sphere of radius `r` whose centre is at `c` from the receiver with
/// unit normal `n`: pi sin^2(alpha) cos(theta) when wholly above the horizon, Snyder's form when
/// the horizon cuts it, 0 when wholly below. `None` from inside or on the sphere.
#[inline]
pub fn sphere_projected_solid_angle(c: Vec3, r: f32, n: Vec3) -> Option<f32> {
    let d2 = c.length_squared();
    let r2 = r * r;
    if !(d2 > r2) || !d2.is_finite() {
        return None;
    }
    let sin2 = r2 / d2;
    let cos = n.dot(c) / sqrt(d2);
    if cos * cos >= sin2 {
        return Some(if cos > 0.0 { PI * sin2 * cos } else { 0.0 });
    }
    // Partly below the horizon (Snyder 1996): with x = cot(alpha), y = -x cot(theta),
    // Omega_perp = (cos(theta) acos(y) - x sin(theta) sqrt(1 - y^2)) sin^2(alpha)
    //            + atan(sin(theta) sqrt(1 - y^2) / x).
    let x = sqrt((d2 - r2) / r2);
    let sin = safe_sqrt(1.0 - cos * cos);
    let y = clamp(-x * cos / sin, -1.0, 1.0);
    let s = sin * safe_sqrt(1.0 - y * y);
    let a = cos * acos(y) * sin2;
    let b = x * s * sin2;
    let c_term = atan2(s, x);
    let value = a - b + c_term;
    let magnitude = a.abs() + b.abs() + c_term.abs();
    (value.is_finite() && value >= 0.0 && value >= MIN_RELATIVE * magnitude).then_some(value)
}

/// Which lights the control variate takes at a shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cover {
    /// Every quad and sphere light (f (V - 1) sampled for those that may be blocked).
    Every,
    /// Only the lights nothing can block from the receiver, where the closed form is exact.
    Unblocked,
    /// [`Cover::Every`] where a light looks large from the receiver (its extent at least the
    /// control variate's [`ControlVariateStrategy::SMALL`] times its distance,
    /// [`Shape::looks_small`]), else [`Cover::Unblocked`].
    Large,
}

impl Cover {
    /// The lights [`crate::integrator::control_variate::Auto`] covers in `scene`: every one in a
    /// scene of area lights only, else the unblocked ones. With a size rule (`Cv::SMALL`, that of
    /// [`crate::integrator::control_variate::BySize`]), a scene's only light where it looks large
    /// ([`Cover::Large`]).
    pub fn auto<Cv: ControlVariateStrategy, const S: usize, const L: usize, const M: usize>(
        scene: &Scene<S, L, M>,
    ) -> Self {
        let lights = scene.lights();
        if !lights.iter().all(|l| matches!(l, Light::Area { .. })) {
            return Cover::Unblocked;
        }
        match Cv::SMALL {
            Some(_) if lights.len() == 1 => Cover::Large,
            _ => Cover::Every,
        }
    }
}

/// What the control variate covers at a shading point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Covered {
    /// Bit i: light i's unoccluded part is in closed form (light i < 64).
    pub lights: u64,
    /// Bit i: light i's part is exact (nothing can block it): it needs no samples.
    pub exact: u64,
    /// The closed-form reflected radiance of the covered lights.
    pub radiance: Rgb,
}

/// The lights whose unoccluded part at `x` has a trusted closed form and that `cover` takes, and
/// their reflected radiance rho / pi sum_i L_i Omega_perp_i, for a Lambertian receiver seen
/// from above its surface (`cos_o` > 0); nothing otherwise. Only sphere and quad lights of the
/// kinds the scene may have ([`SphereSampler::PRESENT`], [`QuadSampler::PRESENT`]) count.
/// (Out of line: once per shading point, and a firmware that carries it shows it by name.)
#[inline(never)]
pub fn unoccluded_light<
    Sp: SphereSampler,
    Q: QuadSampler,
    Cv: ControlVariateStrategy,
    const S: usize,
    const L: usize,
    const M: usize,
>(
    scene: &Scene<S, L, M>,
    bsdf: &Material,
    x: &Hit,
    cos_o: f32,
    cover: Cover,
) -> Covered {
    let Material::Lambertian { albedo } = *bsdf else { return Covered::default() };
    if !(cos_o > 0.0) {
        return Covered::default();
    }
    let cover = match (cover, Cv::SMALL) {
        // Only a strategy with a size rule makes a `Large` cover (`Cover::auto`); without one,
        // the rule's code is left out of the build.
        (Cover::Large, None) => Cover::Every,
        (Cover::Large, Some(ratio)) => {
            let large = scene.lights().iter().take(64).any(|light| {
                let Light::Area { shape: emitter, .. } = *light else { return false };
                scene
                    .shape(emitter)
                    .is_some_and(|shape| emitter != x.object && !shape.looks_small(x.point.p, ratio))
            });
            if large { Cover::Every } else { Cover::Unblocked }
        }
        (other, _) => other,
    };
    let (mut covered, mut exact, mut sum) = (0u64, 0u64, Rgb::ZERO);
    for (i, light) in scene.lights().iter().enumerate().take(64) {
        let Light::Area { shape: emitter, radiance } = *light else { continue };
        if emitter == x.object {
            continue;
        }
        let Some(shape) = scene.shape(emitter) else { continue };
        // Only for the kinds of lights the scene may have.
        let present = if shape.as_sphere().is_some() { Sp::PRESENT } else { Q::PRESENT };
        if !present {
            continue;
        }
        let unblocked = scene.shadow_candidates(x.object, LightId::new(i as u16)) == 0;
        if cover == Cover::Unblocked && !unblocked {
            continue;
        }
        if let Some(omega) = projected_solid_angle(shape, x.point.p, x.point.n) {
            covered |= 1 << i;
            if unblocked {
                exact |= 1 << i;
            }
            sum += radiance * omega;
        }
    }
    Covered { lights: covered, exact, radiance: albedo * INV_PI * sum }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_overhead_and_below() {
        let v = sphere_projected_solid_angle(Vec3::new(0.0, 0.0, 2.0), 1.0, Vec3::Z).unwrap();
        assert!((v - PI * 0.25).abs() < 1e-6);
        assert_eq!(sphere_projected_solid_angle(Vec3::new(0.0, 0.0, -2.0), 1.0, Vec3::Z), Some(0.0));
        assert_eq!(sphere_projected_solid_angle(Vec3::new(0.0, 0.0, 0.5), 1.0, Vec3::Z), None);
    }

    #[test]
    fn huge_quad_overhead_is_pi() {
        let h = 1e4;
        let v = [Vec3::new(-h, -h, 1.0), Vec3::new(-h, h, 1.0), Vec3::new(h, h, 1.0), Vec3::new(h, -h, 1.0)];
        let omega = quad_projected_solid_angle(v, Vec3::Z).unwrap();
        assert!((omega / PI - 1.0).abs() < 1e-3, "{omega}");
        // Seen from behind: nothing.
        let mut back = v;
        back.reverse();
        assert_eq!(quad_projected_solid_angle(back, Vec3::Z), Some(0.0));
    }
}
