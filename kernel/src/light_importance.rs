//! How much light a light may send to a shading point, estimated from the light alone: its
//! radiance (or intensity), the solid angle it subtends, and the cosines at both ends. Light
//! selection by contribution picks lights in proportion to this estimate, O(lights) per sample.
//!
//! The estimate is an importance, not a bound, but it is zero only where the light certainly
//! sends nothing (wholly below the receiver's horizon, the receiver behind a one-sided quad or
//! inside a sphere): any light that can contribute keeps a non-zero probability, so selection by
//! it stays unbiased.

use crate::light::Light;
use crate::math::{PI, Vec3, luminance, max0, safe_sqrt, sqrt};
use crate::sampling::cone_one_minus_cos;
use crate::shape::Shape;

/// Largest cosine between the receiver's normal `n` and any direction in the cone of half-angle
/// theta_max around unit `w` (`sin2_max` = sin^2 theta_max): 1 when the cone holds the normal,
/// else cos(theta - theta_max), clamped at 0 (the cone is wholly below the horizon).
#[inline]
fn max_cosine(n: Vec3, w: Vec3, sin2_max: f32) -> f32 {
    let cos_c = n.dot(w);
    let cos_max = safe_sqrt(1.0 - sin2_max);
    if cos_c >= cos_max {
        return 1.0;
    }
    let sin_c = safe_sqrt(1.0 - cos_c * cos_c);
    max0(cos_c * cos_max + sin_c * sqrt(max0(sin2_max)))
}

/// The importance of `light` (emitting from `shape` for area lights) at point `x` with unit
/// normal `n`: luminance of the radiance times the subtended solid angle times the largest
/// receiver cosine (spheres and quads), or luminance of the intensity over the squared distance
/// times the receiver cosine (point lights). Finite and non-negative for finite input.
pub fn light_importance(light: &Light, shape: Option<&Shape>, x: Vec3, n: Vec3) -> f32 {
    let importance = match *light {
        Light::Point { position, intensity } => {
            let v = position - x;
            let d2 = v.length_squared();
            if !(d2 > 0.0) {
                return 0.0;
            }
            max0(luminance(intensity)) * max0(n.dot(v)) / (d2 * sqrt(d2))
        }
        Light::Area { radiance, .. } => {
            let Some(shape) = shape else { return 0.0 };
            let le = max0(luminance(radiance));
            let c = shape.centroid();
            let v = c - x;
            let d2 = v.length_squared();
            let r = shape.bounding_radius();
            let r2 = r * r;
            match shape.as_sphere() {
                // Inside or on a sphere light: its outward front side faces away.
                Some(_) if !(d2 > r2) => return 0.0,
                Some(_) => {
                    let sin2 = r2 / d2;
                    let w = v / sqrt(d2);
                    le * 2.0 * PI * cone_one_minus_cos(sin2) * max_cosine(n, w, sin2)
                }
                None => {
                    // A quad emits on the side of its normal only; `x` behind its plane sees none.
                    let n_l = shape.normal_at(c);
                    let behind = n_l.dot(-v);
                    if !(behind > 0.0) {
                        return 0.0;
                    }
                    if !(d2 > r2) {
                        // Within the bounding sphere: up to the whole hemisphere.
                        le * 2.0 * PI
                    } else {
                        let d = sqrt(d2);
                        let w = v / d;
                        let solid_angle = (shape.area() * behind / (d2 * d)).min(2.0 * PI);
                        le * solid_angle * max_cosine(n, w, r2 / d2)
                    }
                }
            }
        }
    };
    if importance.is_finite() { importance } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;

    fn area(shape: &Shape, l: f32) -> (Light, Shape) {
        (Light::Area { shape: crate::ids::ShapeId::new(0), radiance: Rgb::splat(l) }, *shape)
    }

    #[test]
    fn a_sphere_overhead_gives_radiance_times_solid_angle() {
        let s = Shape::sphere(Vec3::new(0.0, 10.0, 0.0), 1.0).unwrap();
        let (light, shape) = area(&s, 3.0);
        let got = light_importance(&light, Some(&shape), Vec3::ZERO, Vec3::Y);
        let omega = 2.0 * PI * (1.0 - (1.0f32 - 0.01).sqrt());
        assert!((got / (3.0 * omega) - 1.0).abs() < 1e-4, "{got}");
        // Twice as far: about a quarter.
        let s2 = Shape::sphere(Vec3::new(0.0, 20.0, 0.0), 1.0).unwrap();
        let far = light_importance(&light, Some(&s2), Vec3::ZERO, Vec3::Y);
        assert!((got / far - 4.0).abs() < 0.01, "{}", got / far);
    }

    #[test]
    fn zero_only_where_the_light_cannot_contribute() {
        let s = Shape::sphere(Vec3::new(3.0, 0.5, 0.0), 1.0).unwrap();
        let (light, shape) = area(&s, 1.0);
        // Partly above the horizon (centre 0.5 above, radius 1): positive.
        assert!(light_importance(&light, Some(&shape), Vec3::ZERO, Vec3::Y) > 0.0);
        // Wholly below: zero.
        let below = Shape::sphere(Vec3::new(3.0, -1.5, 0.0), 1.0).unwrap();
        assert_eq!(light_importance(&light, Some(&below), Vec3::ZERO, Vec3::Y), 0.0);
        // Inside: zero.
        assert_eq!(light_importance(&light, Some(&shape), Vec3::new(3.0, 0.5, 0.2), Vec3::Y), 0.0);
        // A ceiling quad facing down: seen from below, not from above.
        let q = Shape::quad([
            Vec3::new(-1.0, 2.0, -1.0),
            Vec3::new(1.0, 2.0, -1.0),
            Vec3::new(1.0, 2.0, 1.0),
            Vec3::new(-1.0, 2.0, 1.0),
        ])
        .unwrap();
        assert!(q.normal_at(Vec3::ZERO).y < 0.0);
        let (ql, qs) = area(&q, 1.0);
        let under = light_importance(&ql, Some(&qs), Vec3::ZERO, Vec3::Y);
        // Far below, about L A / d^2.
        let far = light_importance(&ql, Some(&qs), Vec3::new(0.0, -98.0, 0.0), Vec3::Y);
        assert!((far / (4.0 / 10_000.0) - 1.0).abs() < 1e-3, "{far}");
        assert!(under > far);
        assert_eq!(light_importance(&ql, Some(&qs), Vec3::new(0.0, 3.0, 0.0), Vec3::Y), 0.0);
        // Close to the quad: capped at the hemisphere.
        let close = light_importance(&ql, Some(&qs), Vec3::new(0.0, 1.9, 0.0), Vec3::Y);
        assert!((close - 2.0 * PI).abs() < 1e-5, "{close}");
        // A quad beside a receiver whose horizon cuts it: positive.
        let side = light_importance(&ql, Some(&qs), Vec3::new(3.0, 1.9, 0.0), Vec3::Y);
        assert!(side > 0.0);
        // Point lights: I cos / d^2, zero below the horizon.
        let p = Light::Point { position: Vec3::new(0.0, 2.0, 0.0), intensity: Rgb::splat(8.0) };
        assert!((light_importance(&p, None, Vec3::ZERO, Vec3::Y) - 2.0).abs() < 1e-6);
        assert_eq!(light_importance(&p, None, Vec3::ZERO, -Vec3::Y), 0.0);
        assert_eq!(light_importance(&p, None, Vec3::new(0.0, 2.0, 0.0), Vec3::Y), 0.0);
    }

    #[test]
    fn the_largest_cosine_is_that_of_the_cone_edge_nearest_the_normal() {
        // Cone axis 60 degrees off the normal, half-angle 30: the edge touches the normal.
        let w = Vec3::new(60f32.to_radians().sin(), 60f32.to_radians().cos(), 0.0);
        let s2 = 30f32.to_radians().sin().powi(2);
        assert!((max_cosine(Vec3::Y, w, s2) - 30f32.to_radians().cos()).abs() < 1e-5);
        let s2 = 60f32.to_radians().sin().powi(2);
        assert_eq!(max_cosine(Vec3::Y, w, s2), 1.0);
        // Axis 120 degrees off, half-angle 20: wholly below.
        let w = Vec3::new(120f32.to_radians().sin(), 120f32.to_radians().cos(), 0.0);
        assert_eq!(max_cosine(Vec3::Y, w, 20f32.to_radians().sin().powi(2)), 0.0);
    }
}
