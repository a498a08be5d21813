//! Charts of directions: a polar chart of (part of) the sphere around an axis ([`Cap`]), and the
//! f32 <-> f64 conversions of vectors.

use std::f64::consts::PI;

use glam::DVec3;
use picomis::Vec3;

/// f32 vector to f64.
pub fn d3(v: Vec3) -> DVec3 {
    v.as_dvec3()
}

/// f64 vector to f32.
pub fn f3(v: DVec3) -> Vec3 {
    v.as_vec3()
}

/// An orthonormal frame around unit `n` (f64).
pub fn frame(n: DVec3) -> [DVec3; 3] {
    let n = n.normalize();
    let helper = if n.x.abs() < 0.6 { DVec3::X } else { DVec3::Y };
    let t = helper.cross(n).normalize();
    [t, n.cross(t), n]
}

/// A polar chart of the directions within `theta_max` of an axis: a = theta / theta_max,
/// b = phi / (2 pi). `theta_max = pi` charts the whole sphere, `pi / 2` a hemisphere.
#[derive(Clone, Copy, Debug)]
pub struct Cap {
    /// Tangent, bitangent, axis.
    pub frame: [DVec3; 3],
    /// Largest polar angle charted.
    pub theta_max: f64,
}

impl Cap {
    /// The cap of half-angle `theta_max` around `axis`.
    pub fn new(axis: DVec3, theta_max: f64) -> Self {
        Self { frame: frame(axis), theta_max }
    }

    /// Chart coordinates of direction `v` (any length), `None` beyond `theta_max`.
    /// The polar angle comes from atan2 of the tangential and axial parts, so it stays accurate
    /// for directions a micro-radian off the axis.
    pub fn coords(&self, v: DVec3) -> Option<(f64, f64)> {
        let [t, b, n] = self.frame;
        let (x, y, z) = (v.dot(t), v.dot(b), v.dot(n));
        let theta = (x * x + y * y).sqrt().atan2(z);
        let a = theta / self.theta_max;
        let phi = y.atan2(x).rem_euclid(2.0 * PI);
        (a <= 1.0).then_some((a, phi / (2.0 * PI)))
    }

    /// The unit direction at chart coordinates (a, b).
    pub fn direction(&self, a: f64, b: f64) -> DVec3 {
        let [t, bt, n] = self.frame;
        let (theta, phi) = (a * self.theta_max, b * 2.0 * PI);
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        t * (st * cp) + bt * (st * sp) + n * ct
    }

    /// Solid angle per unit chart area at (a, b): sin(theta) theta_max 2 pi.
    pub fn jacobian(&self, a: f64) -> f64 {
        (a * self.theta_max).sin() * self.theta_max * 2.0 * PI
    }

    /// Density in chart coordinates of a solid-angle `pdf` of directions.
    pub fn density<'a>(&'a self, pdf: impl Fn(DVec3) -> f64 + 'a) -> impl Fn(f64, f64) -> f64 + 'a {
        move |a, b| pdf(self.direction(a, b)) * self.jacobian(a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::histogram::integrate_cell;

    #[test]
    fn cap_chart_round_trips_and_integrates_to_the_solid_angle() {
        let cap = Cap::new(DVec3::new(0.3, -0.5, 0.8), 0.7);
        for (a, b) in [(0.1, 0.2), (0.9, 0.95), (0.5, 0.0)] {
            let (a2, b2) = cap.coords(cap.direction(a, b) * 3.0).unwrap();
            assert!((a - a2).abs() < 1e-12 && ((b - b2 + 0.5).rem_euclid(1.0) - 0.5).abs() < 1e-12);
        }
        assert!(cap.coords(-cap.frame[2]).is_none());
        let area = integrate_cell(&cap.density(|_| 1.0), [0.0, 1.0], [0.0, 1.0], 4);
        assert!((area / (2.0 * PI * (1.0 - 0.7f64.cos())) - 1.0).abs() < 1e-12);
    }
}
