//! Charts of light surfaces for the chi-square tests: the part of a sphere visible from a point,
//! and a parallelogram by its own coordinates, each with the chart density of a solid-angle pdf.

use picomis::Vec3;
use picomis_tests::{DVec3, d3, f3, frame};
use std::f64::consts::PI;

/// The part of a sphere (centre `c`, radius `r`) visible from `x`, charted by
/// a = (1 - cos psi) / (1 - r/d) (area-uniform) and b = phi / 2 pi, psi measured at the centre
/// from the axis towards `x`. The visible cap is exactly psi < acos(r/d).
pub struct VisibleCap {
    x: DVec3,
    c: DVec3,
    r: f64,
    frame: [DVec3; 3],
    omc_max: f64,
}

impl VisibleCap {
    pub fn new(x: Vec3, c: Vec3, r: f32) -> Self {
        let (x, c, r) = (d3(x), d3(c), f64::from(r));
        let d = (x - c).length();
        Self { x, c, r, frame: frame(x - c), omc_max: 1.0 - r / d }
    }

    pub fn coords(&self, y: DVec3) -> Option<(f64, f64)> {
        let [t, b, axis] = self.frame;
        let n = (y - self.c).normalize();
        let a = 0.5 * (n - axis).length_squared() / self.omc_max;
        let phi = n.dot(b).atan2(n.dot(t)).rem_euclid(2.0 * PI);
        (a <= 1.0).then_some((a, phi / (2.0 * PI)))
    }

    /// Chart density of a solid-angle pdf given as a function of the point and its normal:
    /// pdf * cos_y / |x - y|^2 * dA/d(a, b), dA/d(a, b) = r^2 (1 - r/d) 2 pi.
    pub fn density<'a>(&'a self, pdf: impl Fn(Vec3, Vec3) -> f64 + 'a) -> impl Fn(f64, f64) -> f64 + 'a {
        move |a, b| {
            let [t, bt, axis] = self.frame;
            let omc = a * self.omc_max;
            let sin = (omc * (2.0 - omc)).sqrt();
            let (sp, cp) = (b * 2.0 * PI).sin_cos();
            let n = t * (sin * cp) + bt * (sin * sp) + axis * (1.0 - omc);
            let y = self.c + n * self.r;
            let v = self.x - y;
            let d2 = v.length_squared();
            let cos_y = n.dot(v) / d2.sqrt();
            pdf(f3(y), f3(n)) * cos_y / d2 * self.r * self.r * self.omc_max * 2.0 * PI
        }
    }
}

/// A parallelogram light charted by its own (s, t) coordinates.
pub struct QuadChart {
    x: DVec3,
    p0: DVec3,
    e1: DVec3,
    e2: DVec3,
    n: DVec3,
    w: DVec3,
    area: f64,
}

impl QuadChart {
    pub fn new(x: Vec3, corners: [Vec3; 4]) -> Self {
        let (p0, e1, e2) = (d3(corners[0]), d3(corners[1] - corners[0]), d3(corners[3] - corners[0]));
        let c = e1.cross(e2);
        Self { x: d3(x), p0, e1, e2, n: c.normalize(), w: c * (1.0 / c.length_squared()), area: c.length() }
    }

    pub fn coords(&self, y: DVec3) -> Option<(f64, f64)> {
        let d = y - self.p0;
        let (s, t) = (d.cross(self.e2).dot(self.w), self.e1.cross(d).dot(self.w));
        ((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t)).then_some((s, t))
    }

    /// Chart density of a solid-angle pdf: pdf * cos_y / |x - y|^2 * area.
    pub fn density<'a>(&'a self, pdf: impl Fn(Vec3, Vec3) -> f64 + 'a) -> impl Fn(f64, f64) -> f64 + 'a {
        move |s, t| {
            let y = self.p0 + self.e1 * s + self.e2 * t;
            let v = self.x - y;
            let d2 = v.length_squared();
            let cos_y = self.n.dot(v).abs() / d2.sqrt();
            pdf(f3(y), f3(self.n)) * cos_y / d2 * self.area
        }
    }
}
