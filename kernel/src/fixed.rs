//! Fixed-point ray queries ([`Arith::Fixed`](crate::arith::Arith)) for cores without an FPU:
//! closest hit and visibility for spheres and quads in integers, results converted back to f32
//! for shading. Integers give the same bits on every machine.
//!
//! Scale: from the scene's extent B (the largest coordinate magnitude of any shape or the
//! camera), one unit is 2^-(26 - floor(log2 B)), so every scene coordinate is below 2^27 units.
//! Directions are Q30. Bounds (|o| <= 2^28 units, checked per ray; |c|, |p0| < 2^27; |d_i| <=
//! 2^30 + 2^21) keep every i64 product below 2^62. A ray outside those bounds takes the f32 test.
//! A scene whose spheres or quad edges are below 2^12 units, or whose quad axes are too skewed,
//! is rejected at construction ([`SceneError::NotRepresentable`]).

use heapless::Vec;

use crate::error::{SceneError, Unrepresentable};
use crate::math::Vec3;
use crate::shape::{Ray, Shape};

/// Fraction bits of directions and normals.
const Q: u32 = 30;
/// The smallest sphere radius or quad edge, in units.
const MIN_SIZE: f32 = 4096.0;
/// Largest ray origin coordinate magnitude, in units.
const MAX_ORIGIN: i64 = 1 << 28;
/// Largest direction component magnitude, Q30 (a unit vector with rounding).
const MAX_DIR: i64 = (1 << Q) + (1 << 21);
/// Largest dual-axis component, Q30 per unit.
const MAX_AXIS: f32 = 16_777_216.0;
/// Beyond this distance (units) nothing in the scene can be met.
const MAX_T: i64 = 1 << 31;

#[derive(Clone, Copy, Debug, PartialEq)]
enum FixedShape {
    Sphere { c: [i64; 3], r2: i64 },
    Quad { p0: [i64; 3], n: [i64; 3], plane: i64, sa: [i64; 3], ta: [i64; 3] },
}

/// A ray in units (origin) and Q30 (direction).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FixedRay {
    o: [i64; 3],
    d: [i64; 3],
    ok: bool,
}

/// The fixed-point copies of a scene's shapes and its scale.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct FixedScene<const S: usize> {
    /// 2^s: world to units.
    scale: f32,
    /// 2^-s.
    inv: f32,
    shapes: Vec<FixedShape, S>,
}

fn pow2(e: i32) -> f32 {
    f32::from_bits(((127 + e.clamp(-126, 127)) as u32) << 23)
}

fn v3(v: Vec3, k: f32) -> [i64; 3] {
    [(v.x * k) as i64, (v.y * k) as i64, (v.z * k) as i64]
}

fn dot(a: &[i64; 3], b: &[i64; 3]) -> i64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// floor(sqrt(x)) for x >= 0 (bit by bit, integer only).
fn isqrt(x: i64) -> i64 {
    let mut x = x.max(0) as u64;
    let mut r: u64 = 0;
    let mut bit: u64 = 1 << 62;
    while bit > x {
        bit >>= 2;
    }
    while bit != 0 {
        if x >= r + bit {
            x -= r + bit;
            r = (r >> 1) + bit;
        } else {
            r >>= 1;
        }
        bit >>= 2;
    }
    r as i64
}

impl<const S: usize> FixedScene<S> {
    /// The fixed-point scene of `shapes` seen from `camera`, or why it cannot be represented.
    pub(crate) fn new<'a>(
        shapes: impl Iterator<Item = &'a Shape> + Clone,
        camera: Vec3,
    ) -> Result<Self, SceneError> {
        let mut b = camera.abs().max_element();
        for shape in shapes.clone() {
            let e = match shape {
                Shape::Sphere(s) => {
                    let (c, r) = s.center_radius();
                    c.abs().max_element() + r
                }
                Shape::Quad(_) => shape
                    .corners()
                    .map_or(0.0, |cs| cs.iter().fold(0.0f32, |m, c| m.max(c.abs().max_element()))),
            };
            b = b.max(e);
        }
        if !b.is_finite() {
            return Err(SceneError::NotRepresentable { entry: 0, reason: Unrepresentable::Extent });
        }
        let e = (((b.to_bits() >> 23) & 0xff) as i32 - 127).max(-100);
        let s = 26 - e;
        let (scale, inv) = (pow2(s), pow2(-s));
        let mut out = Vec::new();
        for (i, shape) in shapes.enumerate() {
            let entry = i as u16;
            let small = SceneError::NotRepresentable { entry, reason: Unrepresentable::TooSmall };
            let f = match shape {
                Shape::Sphere(sp) => {
                    let (c, r) = sp.center_radius();
                    let ru = r * scale;
                    if !(ru >= MIN_SIZE) {
                        return Err(small);
                    }
                    let r = ru as i64;
                    FixedShape::Sphere { c: v3(c, scale), r2: r * r }
                }
                Shape::Quad(q) => {
                    let (p0, e1, e2) = q.edges();
                    if !(e1.length() * scale >= MIN_SIZE && e2.length() * scale >= MIN_SIZE) {
                        return Err(small);
                    }
                    let (n, _, _, sa, ta) = q.parts();
                    let k = pow2(Q as i32 - s);
                    if !(sa.abs().max_element() * k < MAX_AXIS && ta.abs().max_element() * k < MAX_AXIS) {
                        return Err(SceneError::NotRepresentable { entry, reason: Unrepresentable::Skewed });
                    }
                    let p0 = v3(p0, scale);
                    let n = v3(n, pow2(Q as i32));
                    FixedShape::Quad { p0, n, plane: dot(&n, &p0), sa: v3(sa, k), ta: v3(ta, k) }
                }
            };
            out.push(f).map_err(|_| SceneError::CapacityExceeded(crate::error::Collection::Shapes))?;
        }
        Ok(Self { scale, inv, shapes: out })
    }

    /// The fixed-point copy of `ray`.
    pub(crate) fn ray(&self, ray: &Ray) -> FixedRay {
        let o = v3(ray.origin, self.scale);
        let d = v3(ray.dir, pow2(Q as i32));
        let ok = o.iter().all(|v| v.abs() <= MAX_ORIGIN) && d.iter().all(|v| v.abs() <= MAX_DIR);
        FixedRay { o, d, ok }
    }

    fn units(&self, t: f32) -> i64 {
        (t * self.scale) as i64
    }

    /// Distance to the hit of shape `i` (whose f32 form is `shape`) in `(t_min, t_max)`.
    pub(crate) fn intersect(
        &self,
        i: usize,
        shape: &Shape,
        ray: &Ray,
        fr: &FixedRay,
        t_min: f32,
        t_max: f32,
    ) -> Option<f32> {
        if !fr.ok {
            return shape.intersect(ray, t_min, t_max);
        }
        let (lo, hi) = (self.units(t_min), self.units(t_max).min(MAX_T));
        let inside = |t: i64| t > lo && t < hi;
        let t = match self.shapes.get(i)? {
            FixedShape::Sphere { c, r2 } => {
                let f = [fr.o[0] - c[0], fr.o[1] - c[1], fr.o[2] - c[2]];
                let b = dot(&f, &fr.d) >> Q;
                let l =
                    [f[0] - ((fr.d[0] * b) >> Q), f[1] - ((fr.d[1] * b) >> Q), f[2] - ((fr.d[2] * b) >> Q)];
                let disc = r2 - dot(&l, &l);
                if disc < 0 {
                    return None;
                }
                let h = isqrt(disc);
                let (near, far) = (-b - h, -b + h);
                if inside(near) {
                    near
                } else if inside(far) {
                    far
                } else {
                    return None;
                }
            }
            FixedShape::Quad { p0, n, plane, sa, ta } => {
                let denom = dot(n, &fr.d) >> Q;
                let num = plane - dot(n, &fr.o);
                if denom == 0 || (num < 0) != (denom < 0) {
                    return None;
                }
                let t = num.checked_div(denom)?;
                if !inside(t) {
                    return None;
                }
                let q = [
                    fr.o[0] + ((fr.d[0] * t) >> Q) - p0[0],
                    fr.o[1] + ((fr.d[1] * t) >> Q) - p0[1],
                    fr.o[2] + ((fr.d[2] * t) >> Q) - p0[2],
                ];
                let (s, v) = (dot(&q, sa), dot(&q, ta));
                let one = 1i64 << Q;
                if !((0..=one).contains(&s) && (0..=one).contains(&v)) {
                    return None;
                }
                t
            }
        };
        Some(t as f32 * self.inv)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isqrt_is_floor_sqrt() {
        for x in [0i64, 1, 2, 3, 4, 15, 16, 17, 1 << 40, (1 << 60) + 12345, i64::MAX] {
            let r = isqrt(x);
            assert!(r * r <= x && (r + 1).checked_mul(r + 1).is_none_or(|s| s > x), "{x}");
        }
    }

    #[test]
    fn agrees_with_f32_on_a_sphere_and_a_quad() {
        let shapes = [
            Shape::sphere(Vec3::new(0.0, 0.0, -3.0), 1.0).unwrap(),
            Shape::quad([
                Vec3::new(-2.0, -1.0, 2.0),
                Vec3::new(2.0, -1.0, 2.0),
                Vec3::new(2.0, -1.0, -6.0),
                Vec3::new(-2.0, -1.0, -6.0),
            ])
            .unwrap(),
        ];
        let fx: FixedScene<2> = FixedScene::new(shapes.iter(), Vec3::new(0.0, 0.0, 1.0)).unwrap();
        let (mut hits, mut differ) = (0, 0);
        for k in 0..200 {
            let a = k as f32 * 0.031;
            let dir = Vec3::new(a.sin() * 0.4, a.cos() * 0.3 - 0.2, -1.0).normalize();
            let ray = Ray { origin: Vec3::new(0.0, 0.0, 1.0), dir };
            let fr = fx.ray(&ray);
            for (i, s) in shapes.iter().enumerate() {
                let want = s.intersect(&ray, 0.0, f32::INFINITY);
                let got = fx.intersect(i, s, &ray, &fr, 0.0, f32::INFINITY);
                match (want, got) {
                    (Some(w), Some(g)) => {
                        hits += 1;
                        assert!((w - g).abs() < 1e-4, "{w} {g}");
                    }
                    (None, None) => {}
                    // Grazing rays may differ by a rounding either way.
                    _ => differ += 1,
                }
            }
        }
        assert!(hits > 100 && differ <= 2, "{hits} hits, {differ} differ");
    }

    #[test]
    fn tiny_sphere_is_rejected_with_its_entry() {
        let shapes = [
            Shape::sphere(Vec3::new(0.0, 0.0, -3.0), 1.0).unwrap(),
            Shape::sphere(Vec3::new(0.0, 0.0, -100.0), 1e-4).unwrap(),
        ];
        let r: Result<FixedScene<2>, _> = FixedScene::new(shapes.iter(), Vec3::ZERO);
        assert_eq!(r, Err(SceneError::NotRepresentable { entry: 1, reason: Unrepresentable::TooSmall }));
    }
}
