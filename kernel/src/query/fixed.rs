//! Fixed-point ray queries ([`Arith::Fixed`](crate::query::Arith), feature `fixed`) for cores
//! without an FPU: closest hit and visibility for spheres and quads in integers, results
//! converted back to f32 for shading. Integers give the same bits on every machine.
//!
//! Scale: from the scene's extent B (the largest coordinate magnitude of any shape or the
//! camera), one unit is 2^-(26 - floor(log2 B)), so every scene coordinate is below 2^27 units.
//! Directions and normals are Q30. Bounds (|o| <= 2^28 units, checked per ray; |c|, |p0| <
//! 2^27; |d_i| <= 2^30 + 2^21; dual axes below 2^28) keep every i64 sum of products below 2^62. A ray
//! outside those bounds (or not finite) takes the f32 test. A scene whose spheres or quad edges
//! are below 2^12 units, or whose quad axes are too skewed, is rejected at construction
//! ([`SceneError::NotRepresentable`]).
//!
//! A quad's dual axes (e / |e|^2 for a rectangle: the edge coordinate per unit) are small
//! numbers, about 2^30 / (edge length in units): a quad as large as the scene would keep only a
//! few bits of them in Q30. So each quad has its own fraction bits, Q30 plus as many as keep its
//! axes below 2^28 (`AXIS_BITS`): every quad's edge coordinates have 27 or more significant bits.
//!
//! The copies are kept in the scene ([`FixedScene`]) and filled there in place, shape by shape
//! (no copy of the whole table on the stack); stored as i32 where the bounds allow (RAM).

use heapless::Vec;

use crate::error::{Collection, SceneError, Unrepresentable};
use crate::geometry::{Ray, Shape};
use crate::num::Vec3;
#[cfg(all(target_arch = "arm", target_os = "none", target_abi = "eabi"))]
use crate::num::int_m0::{div_steps, dot32};
use crate::num::wide::mul_wide;
use crate::query::accel::Target;

/// Fraction bits of directions and normals.
const Q: u32 = 30;
/// The smallest sphere radius or quad edge, in units.
const MIN_SIZE: f32 = 4096.0;
/// Largest ray origin coordinate magnitude, in units.
const MAX_ORIGIN: i64 = 1 << 28;
/// Largest direction component magnitude, Q30 (a unit vector with rounding).
const MAX_DIR: i64 = (1 << Q) + (1 << 21);
/// Largest dual-axis component, Q30 per unit (more is a skew the format rejects).
const MAX_AXIS: f32 = 16_777_216.0; // 2^24
/// A quad's dual axes are stored below 2^AXIS_BITS, with its own fraction bits.
const AXIS_BITS: i32 = 28;
/// Beyond this distance (units) nothing in the scene can be met.
const MAX_T: i64 = 1 << 31;

/// A shape in units (positions), Q30 (normal) and Q30 per unit (dual axes).
#[derive(Clone, Copy, Debug, PartialEq)]
enum FixedShape {
    /// Centre, radius and squared radius.
    Sphere { c: [i32; 3], r: i32, r2: i64 },
    /// Corner, unit normal, plane offset `n . p0` (Q30 units), dual axes with the quad's own
    /// fraction bits per unit, and one in those bits (2^(Q + extra): no variable 64-bit shift
    /// per test).
    Quad { p0: [i32; 3], n: [i32; 3], plane: i64, sa: [i32; 3], ta: [i32; 3], one: i64 },
}

/// A ray in units (origin) and Q30 (direction), with its open distance range `(lo, hi)` in
/// units. The origin (at most 2^28) and the direction (at most 2^30 + 2^21) fit 32 bits: their
/// products are one 32 x 32 -> 64-bit multiply each (`mul` and `mulh` on RV32IMC, where a full
/// 64-bit multiply takes several).
#[derive(Clone, Copy, Debug, PartialEq)]
struct FixedRay {
    o: [i32; 3],
    d: [i32; 3],
    lo: i64,
    hi: i64,
}

/// The fixed-point copies of a scene's shapes (one per object, in order) and their scale, while
/// the ray queries run in fixed point; empty and off otherwise.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct FixedScene<const S: usize> {
    /// s: world to units is 2^s.
    shift: i32,
    /// 2^-s.
    inv: f32,
    shapes: Vec<FixedShape, S>,
    on: bool,
}

fn pow2(e: i32) -> f32 {
    f32::from_bits(((127 + e.clamp(-126, 127)) as u32) << 23)
}

fn v3(v: Vec3, k: f32) -> [i32; 3] {
    [(v.x * k) as i32, (v.y * k) as i32, (v.z * k) as i32]
}

fn wide(v: &[i32; 3]) -> [i64; 3] {
    [i64::from(v[0]), i64::from(v[1]), i64::from(v[2])]
}

fn dot(a: &[i64; 3], b: &[i64; 3]) -> i64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a . b` of 32-bit vectors in 64 bits (each product exact; on the M0: `int_m0.rs`'s routine).
#[cfg(not(all(target_arch = "arm", target_os = "none", target_abi = "eabi")))]
fn dot32(a: &[i32; 3], b: &[i32; 3]) -> i64 {
    mul_wide(a[0], b[0]) + mul_wide(a[1], b[1]) + mul_wide(a[2], b[2])
}

/// `(d b) >> Q` for a direction component and a distance below 2^31 (in 64 bits: exact).
fn along(d: i32, b: i32) -> i64 {
    mul_wide(d, b) >> Q
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

/// Soft-float Arm cores (the Cortex-M0 class): no divide instruction at all.
const NO_DIVIDER: bool = cfg!(all(target_arch = "arm", not(target_abi = "eabihf")));

/// floor(n / d) for 0 <= n < 2^31 d and 1 <= d <= 2^31, bit by bit in 32-bit registers
/// ([`div_steps`]): the remainder stays below d <= 2^31, so twice it plus a bit fits a u32, and
/// n >> 31 < d starts it. Replaces the 64-bit division (compiler-builtins' `__aeabi_uldivmod`,
/// hundreds of instructions on the M0), which a quad test pays once per plane hit in range.
/// Outside the bounds (never reached: the quad test's range check implies them), the 64-bit
/// division.
#[inline]
fn div_floor(n: i64, d: i64) -> i64 {
    if !(n >= 0 && (1..=1 << 31).contains(&d) && n >> 31 < d) {
        return n.checked_div(d).unwrap_or(0);
    }
    // The remainder starts as the dividend's bits from 31 up (< d); its bits 30..0 go on top.
    i64::from(div_steps((n >> 31) as u32, (n as u32) << 1, d as u32))
}

/// The 31 steps of restoring division: `rem` < `d` <= 2^31 holds the dividend's leading bits,
/// `w` the 31 bits after them on top; each step shifts one of them into the remainder and the
/// quotient bit in at the bottom of `w`, which ends as the quotient. (On the M0: one call to
/// `int_m0.rs`'s routine, the same steps in Thumb-1.)
#[cfg(not(all(target_arch = "arm", target_os = "none", target_abi = "eabi")))]
#[inline]
fn div_steps(mut rem: u32, mut w: u32, d: u32) -> u32 {
    for _ in 0..31 {
        rem = (rem << 1) | (w >> 31);
        w <<= 1;
        if rem >= d {
            rem -= d;
            w |= 1;
        }
    }
    w
}

/// floor(n / d) for 0 <= n < 2^31 d and 1 <= d <= 2^31, as [`div_floor`], from two 32-by-16-bit
/// digit divisions (Knuth's algorithm D for two digits of 16 bits, after Hacker's Delight's
/// `divlu`): for 32-bit cores that divide 32-bit integers in one instruction (RV32IM's `divu`),
/// where the 64-bit division is compiler-builtins' `u64_div_rem` (hundreds of instructions on
/// RV32IMC), and so does the bit loop. d is shifted up until its top bit is set, so that each
/// digit's estimate from the divisor's top 16 bits is at most two too large and the corrections
/// end. Outside the bounds, the 64-bit division.
#[inline]
fn div_floor_digits(n: i64, d: i64) -> i64 {
    if !(n >= 0 && (1..=1 << 31).contains(&d) && n >> 31 < d) {
        return n.checked_div(d).unwrap_or(0);
    }
    const B: u32 = 1 << 16;
    let (hi, lo, d) = ((n >> 32) as u32, n as u32, d as u32); // hi < d: the quotient fits 32 bits
    let s = d.leading_zeros();
    let v = d << s;
    // The dividend shifted by s too: 64 bits (un32, un10), un32 < v.
    let un32 = if s == 0 { hi } else { (hi << s) | (lo >> (32 - s)) };
    let un10 = lo << s;
    let (vn1, vn0) = (v >> 16, v & 0xffff);
    // One quotient digit of (top, next) / v with top < v: the estimate from v's top half, made
    // exact by at most two decrements; its remainder fits 32 bits.
    let digit = |top: u32, next: u32| {
        let (mut q, mut rhat) = (top / vn1, top % vn1);
        while q >= B || q * vn0 > (rhat << 16 | next) {
            q -= 1;
            rhat += vn1;
            if rhat >= B {
                break;
            }
        }
        (q, (top << 16 | next).wrapping_sub(q.wrapping_mul(v)))
    };
    let (q1, rem) = digit(un32, un10 >> 16);
    let (q0, _) = digit(rem, un10 & 0xffff);
    i64::from(q1 << 16 | q0)
}

/// |x| 2^s as (exponent e, significand m) with |x| 2^s = m 2^(e - 23), m < 2^24, for s <= 126
/// (e below 0 for subnormal x), and the sign; `None` for NaN. The bits of x, no soft-float call.
#[inline(always)]
fn scaled_parts(x: f32, s: i32) -> Option<(i32, u32, bool)> {
    let b = x.to_bits();
    let a = b & 0x7fff_ffff;
    if a > 0x7f80_0000 {
        return None;
    }
    Some(((a >> 23) as i32 - 127 + s, (a & 0x7f_ffff) | 0x80_0000, b >> 31 != 0))
}

/// trunc(x 2^s) for s <= 126 (`None` for NaN) from the bits of x, with no soft-float call:
/// what `(x * 2^s) as i64` gives for |x 2^s| < 2^40, and +-2^40 beyond (infinities too). The
/// reference of the 32-bit conversions [`bounded`] and [`clamped`].
#[cfg(test)]
fn trunc_scaled(x: f32, s: i32) -> Option<i64> {
    let (e, m, negative) = scaled_parts(x, s)?;
    let v = if e < 0 {
        0
    } else if e >= 40 {
        1i64 << 40
    } else {
        let m = i64::from(m);
        if e >= 23 { m << (e - 23) } else { m >> (23 - e) }
    };
    Some(if negative { -v } else { v })
}

/// trunc(x 2^s) when its magnitude is at most `max` (below 2^31; `None` for NaN), in 32-bit
/// shifts (a magnitude of 2^31 or more exceeds `max`; 64-bit shifts are library calls on the
/// 32-bit cores, eight per ray before).
#[inline]
fn bounded(x: f32, s: i32, max: i64) -> Option<i32> {
    let (e, m, negative) = scaled_parts(x, s)?;
    let v = if e < 0 {
        0
    } else if e <= 23 {
        m >> (23 - e)
    } else if e < 31 {
        m << (e - 23) // below 2^31
    } else {
        return None;
    };
    if i64::from(v) > max {
        return None;
    }
    // v < 2^31: no wrap.
    Some(if negative { -(v as i32) } else { v as i32 })
}

/// trunc(x 2^s) limited to [-MAX_T, MAX_T] (`MAX_T` = 2^31), 0 for NaN: a ray's distance bound,
/// in 32-bit shifts like [`bounded`].
#[inline]
fn clamped(x: f32, s: i32) -> i64 {
    let Some((e, m, negative)) = scaled_parts(x, s) else { return 0 };
    let v = if e < 0 {
        0
    } else if e <= 23 {
        i64::from(m >> (23 - e))
    } else if e < 31 {
        i64::from(m << (e - 23))
    } else {
        MAX_T
    };
    if negative { -v } else { v }
}

/// The exponent s of the scale 2^s for `shapes` seen from `camera`.
fn exponent<'a>(shapes: impl Iterator<Item = &'a Shape>, camera: Vec3) -> Result<i32, SceneError> {
    let mut b = camera.abs().max_element();
    for shape in shapes {
        let e = match shape.as_sphere() {
            Some((c, r)) => c.abs().max_element() + r,
            None => {
                shape.corners().map_or(0.0, |cs| cs.iter().fold(0.0f32, |m, c| m.max(c.abs().max_element())))
            }
        };
        // NaN-propagating: a NaN extent is not finite below.
        b = if e > b || e.is_nan() { e } else { b };
    }
    if !b.is_finite() {
        return Err(SceneError::NotRepresentable { entry: 0, reason: Unrepresentable::Extent });
    }
    let e = (((b.to_bits() >> 23) & 0xff) as i32 - 127).max(-100);
    Ok(26 - e)
}

/// Shape `entry` at the scale 2^s, or why the format cannot represent it.
fn convert(shape: &Shape, entry: usize, s: i32) -> Result<FixedShape, SceneError> {
    let entry = u16::try_from(entry).map_err(|_| SceneError::CapacityExceeded(Collection::Shapes))?;
    let fail = |reason| SceneError::NotRepresentable { entry, reason };
    let scale = pow2(s);
    match shape {
        Shape::Sphere(_) => {
            let (c, r) = shape.as_sphere().ok_or_else(|| fail(Unrepresentable::Extent))?;
            let ru = r * scale;
            if !(ru >= MIN_SIZE) {
                return Err(fail(Unrepresentable::TooSmall));
            }
            let r = ru as i32; // below 2^27
            Ok(FixedShape::Sphere { c: v3(c, scale), r, r2: i64::from(r) * i64::from(r) })
        }
        Shape::Quad(q) => {
            let (p0, e1, e2) = q.edges();
            if !(e1.length() * scale >= MIN_SIZE && e2.length() * scale >= MIN_SIZE) {
                return Err(fail(Unrepresentable::TooSmall));
            }
            let (n, _, _, sa, ta) = q.parts();
            let k = pow2(Q as i32 - s);
            let largest = sa.abs().max_element().max(ta.abs().max_element()) * k;
            if !(largest < MAX_AXIS) {
                return Err(fail(Unrepresentable::Skewed));
            }
            // Extra fraction bits: the most that keep the largest component below 2^AXIS_BITS
            // (largest >= 2^-2: an edge is at most 2^29 units; at most 32 extra bits).
            let log2 = ((largest.to_bits() >> 23) & 0xff) as i32 - 127;
            let extra = (AXIS_BITS - 1 - log2).clamp(0, 32);
            let e = Q as i32 - s + extra;
            if !(-126..=127).contains(&(Q as i32 - s)) || !(-126..=127).contains(&e) {
                return Err(fail(Unrepresentable::Extent)); // a scale 2^e an f32 cannot hold
            }
            let ka = pow2(e);
            let (p0, n) = (v3(p0, scale), v3(n, pow2(Q as i32)));
            let plane = dot(&wide(&n), &wide(&p0));
            Ok(FixedShape::Quad {
                p0,
                n,
                plane,
                sa: v3(sa, ka),
                ta: v3(ta, ka),
                one: 1 << (Q as i32 + extra),
            })
        }
    }
}

/// The distance to `shape` along `r` in `(r.lo, r.hi)`, in units.
#[inline]
fn distance(shape: &FixedShape, r: &FixedRay) -> Option<i64> {
    let inside = |t: i64| t > r.lo && t < r.hi;
    match shape {
        FixedShape::Sphere { c, r: radius, r2 } => {
            // 32 bits each: |f[i]| < 2^28 + 2^27, and |b| <= sum |f[i] d[i]| 2^-30 < 3 (2^28 +
            // 2^27) (1 + 2^-9) < 2^31.
            let f = [r.o[0] - c[0], r.o[1] - c[1], r.o[2] - c[2]];
            let b = (dot32(&f, &r.d) >> Q) as i32;
            // Cheap rejects before the rest: both hits are at or beyond -b - r (h <= r), and a
            // centre behind an origin outside the sphere (a coordinate of f beyond r) is missed.
            let (b64, rad) = (i64::from(b), i64::from(*radius));
            if -b64 - rad >= r.hi || (b > 0 && f.iter().any(|&x| i64::from(x).abs() > rad)) {
                return None;
            }
            let f = wide(&f);
            let l = [f[0] - along(r.d[0], b), f[1] - along(r.d[1], b), f[2] - along(r.d[2], b)];
            let disc = r2 - dot(&l, &l);
            if disc < 0 {
                return None;
            }
            let h = isqrt(disc);
            let (near, far) = (-b64 - h, -b64 + h);
            if inside(near) {
                Some(near)
            } else if inside(far) {
                Some(far)
            } else {
                None
            }
        }
        FixedShape::Quad { p0, n, plane, sa, ta, one } => {
            let denom = dot32(n, &r.d) >> Q;
            let num = plane - dot32(n, &r.o);
            if denom == 0 || (num < 0) != (denom < 0) {
                return None;
            }
            // t = floor(num / denom) >= 0 is in (lo, hi) exactly when |num| >= (lo + 1) |denom|
            // and |num| < hi |denom|: no division for the planes out of range (|denom| <= 2^31,
            // hi <= 2^31: the products fit).
            let (an, ad) = (num.abs(), denom.abs());
            if an >= r.hi * ad || an < (r.lo + 1) * ad {
                return None;
            }
            // The M0 has no divider: `div_floor` there; other 32-bit cores have a 32-bit one.
            let t = if NO_DIVIDER {
                div_floor(an, ad)
            } else if cfg!(target_pointer_width = "32") {
                div_floor_digits(an, ad)
            } else {
                an.checked_div(ad)?
            };
            // 0 <= t < hi <= 2^31: 32 bits.
            let (o, p0, t32) = (wide(&r.o), wide(p0), t as i32);
            let q = [
                o[0] + along(r.d[0], t32) - p0[0],
                o[1] + along(r.d[1], t32) - p0[1],
                o[2] + along(r.d[2], t32) - p0[2],
            ];
            let (s, v) = (dot(&q, &wide(sa)), dot(&q, &wide(ta)));
            // |q| < 2^31.2 (|o| <= 2^28, the step d t below 2^31, |p0| < 2^27) and the axes are
            // below 2^28: each sum of products below 2^61.
            ((0..=*one).contains(&s) && (0..=*one).contains(&v)).then_some(t)
        }
    }
}

impl<const S: usize> FixedScene<S> {
    /// Off: no copies, the ray queries run in f32.
    pub(crate) const fn off() -> Self {
        Self { shift: 0, inv: 1.0, shapes: Vec::new(), on: false }
    }

    /// Whether the ray queries run in fixed point.
    #[inline(always)]
    pub(crate) fn is_on(&self) -> bool {
        self.on
    }

    /// Back to f32: drops the copies.
    pub(crate) fn turn_off(&mut self) {
        self.shapes.clear();
        self.on = false;
    }

    /// Whether the format can represent `shapes` seen from `camera` (`Err` names the first shape
    /// it cannot). Stores nothing.
    pub(crate) fn check<'a>(
        shapes: impl Iterator<Item = &'a Shape> + Clone,
        camera: Vec3,
    ) -> Result<(), SceneError> {
        let s = exponent(shapes.clone(), camera)?;
        shapes.enumerate().try_for_each(|(i, shape)| convert(shape, i, s).map(|_| ()))
    }

    /// Turns fixed point on for `shapes` (every object's, in order) seen from `camera`: the scale
    /// from their extent, then the copies, pushed one by one. On an error the queries stay f32.
    pub(crate) fn turn_on<'a>(
        &mut self,
        shapes: impl Iterator<Item = &'a Shape> + Clone,
        camera: Vec3,
    ) -> Result<(), SceneError> {
        self.turn_off();
        let result = self.fill(shapes, camera);
        if result.is_err() {
            self.turn_off();
        }
        result
    }

    fn fill<'a>(
        &mut self,
        shapes: impl Iterator<Item = &'a Shape> + Clone,
        camera: Vec3,
    ) -> Result<(), SceneError> {
        let s = exponent(shapes.clone(), camera)?;
        for (i, shape) in shapes.enumerate() {
            let f = convert(shape, i, s)?;
            self.shapes.push(f).map_err(|_| SceneError::CapacityExceeded(Collection::Shapes))?;
        }
        (self.shift, self.inv, self.on) = (s, pow2(-s), true);
        Ok(())
    }

    /// `ray` with the range `(t_min, t_max)` in fixed point, or `None` when it is outside the
    /// format's bounds. (Always inline: returned out of line, the 16 words went through `memcpy`
    /// on RV32IMC.)
    #[inline(always)]
    fn ray(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<FixedRay> {
        let (k, q) = (self.shift, Q as i32);
        let o = [
            bounded(ray.origin.x, k, MAX_ORIGIN)?,
            bounded(ray.origin.y, k, MAX_ORIGIN)?,
            bounded(ray.origin.z, k, MAX_ORIGIN)?,
        ];
        let d = [
            bounded(ray.dir.x, q, MAX_DIR)?,
            bounded(ray.dir.y, q, MAX_DIR)?,
            bounded(ray.dir.z, q, MAX_DIR)?,
        ];
        // Saturating conversions (+inf is 2^40, NaN is 0), then clamped: the quad test's
        // products stay in range.
        let (lo, hi) = (clamped(t_min, k), clamped(t_max, k));
        Some(FixedRay { o, d, lo, hi })
    }

    /// The nearest hit in `(t_min, t_max)` along `ray` among the `objects` (the scene's, in order)
    /// that `keep` admits, as `(distance, index)`: the lowest index among equal distances. With
    /// `any`, the first hit found. A ray outside the format's bounds takes the f32 test.
    #[inline]
    pub(crate) fn nearest<T: Target>(
        &self,
        objects: &[T],
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        any: bool,
        keep: impl Fn(usize) -> bool,
    ) -> Option<(f32, usize)> {
        let Some(mut r) = self.ray(ray, t_min, t_max) else {
            let (mut t_far, mut best) = (t_max, None);
            for (i, o) in objects.iter().enumerate() {
                if keep(i) {
                    if let Some(t) = o.shape().intersect(ray, t_min, t_far) {
                        (t_far, best) = (t, Some(i));
                        if any {
                            break;
                        }
                    }
                }
            }
            return best.map(|i| (t_far, i));
        };
        let mut best = None;
        for (i, f) in self.shapes.iter().enumerate() {
            if keep(i) {
                if let Some(t) = distance(f, &r) {
                    (r.hi, best) = (t, Some(i));
                    if any {
                        break;
                    }
                }
            }
        }
        best.map(|i| (r.hi as f32 * self.inv, i))
    }

    /// The distance to object `i` (shape `shape`) along `ray` in `(t_min, t_max)`.
    #[inline]
    pub(crate) fn intersect(
        &self,
        i: usize,
        shape: &Shape,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<f32> {
        match self.ray(ray, t_min, t_max) {
            Some(r) => distance(self.shapes.get(i)?, &r).map(|t| t as f32 * self.inv),
            None => shape.intersect(ray, t_min, t_max),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    impl Target for Shape {
        fn shape(&self) -> &Shape {
            self
        }
        fn emits(&self) -> bool {
            false
        }
    }

    fn scene<const S: usize>(shapes: &[Shape], camera: Vec3) -> Result<FixedScene<S>, SceneError> {
        let mut fx = FixedScene::off();
        fx.turn_on(shapes.iter(), camera)?;
        Ok(fx)
    }

    #[test]
    fn trunc_scaled_is_the_cast_of_the_product() {
        let mut x = 0x9e37_79b9u32;
        for _ in 0..100_000 {
            x = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
            let v = f32::from_bits(x);
            for s in [-20, 0, 5, 22, 30] {
                let want = (v * pow2(s)) as i64;
                let want = if v.is_nan() { None } else { Some(want.clamp(-(1 << 40), 1 << 40)) };
                assert_eq!(trunc_scaled(v, s), want, "{v:e} 2^{s}");
            }
        }
        assert_eq!(trunc_scaled(f32::INFINITY, 3), Some(1 << 40));
        assert_eq!(trunc_scaled(-1.5, 1), Some(-3));
    }

    /// `bounded` and `clamped`, in 32 bits, are `trunc_scaled` limited to `max` and clamped to
    /// `MAX_T`: random bits and every binade around the bounds, with both signs.
    #[test]
    fn the_32_bit_conversions_are_the_limited_trunc_scaled() {
        let mut x = 0x2545_f491u32;
        let randoms = (0..100_000).map(|_| {
            x = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
            x
        });
        let edges = (0..=255u32).flat_map(|e| [0, 1, 0x40_0000, 0x7f_ffff].map(|f| e << 23 | f));
        for bits in randoms.chain(edges) {
            for v in [f32::from_bits(bits), -f32::from_bits(bits & 0x7fff_ffff)] {
                for (s, max) in [
                    (-20, MAX_ORIGIN),
                    (0, MAX_ORIGIN),
                    (5, MAX_ORIGIN),
                    (Q as i32, MAX_DIR),
                    (30, (1 << 31) - 1),
                ] {
                    let want = trunc_scaled(v, s).filter(|t| t.abs() <= max).map(|t| t as i32);
                    assert_eq!(bounded(v, s, max), want, "{v:e} 2^{s} max {max}");
                    let want = trunc_scaled(v, s).unwrap_or(0).clamp(-MAX_T, MAX_T);
                    assert_eq!(clamped(v, s), want, "{v:e} 2^{s} clamped");
                }
            }
        }
    }

    /// `div_floor` and `div_floor_digits` equal the 64-bit division over their bounds' edges and
    /// a random sample of them (and outside them too).
    #[test]
    fn div_floor_is_the_division() {
        let check = |n: i64, d: i64| {
            assert_eq!(div_floor(n, d), n / d, "{n} / {d}");
            assert_eq!(div_floor_digits(n, d), n / d, "digits: {n} / {d}");
        };
        let ds = [1i64, 2, 3, 5, 0x7fff, 0x1_0000, 0x7fff_ffff, 1 << 30, (1 << 30) + 1, 1 << 31];
        for d in ds {
            let top = (1i64 << 31) * d; // n < top
            for n in [0, 1, d - 1, d, d + 1, 2 * d - 1, top / 2, top - d - 1, top - d, top - 1] {
                check(n.max(0), d);
            }
            check(top, d); // outside the bounds: the fallback
        }
        let mut x = 0x2545_f491_4f6c_dd1du64;
        for i in 0..if cfg!(debug_assertions) { 200_000 } else { 4_000_000 } {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            // Divisors of every magnitude up to 2^31, quotients of every magnitude below 2^31.
            let d = ((x >> 33) >> (x & 31)).max(1) as i64 + (i & 1);
            let q = ((x >> 8) as u32 >> ((x >> 40) & 31)) as i64 & 0x7fff_ffff;
            let r = (x as i64 & 0x7fff_ffff) % d;
            check(q * d + r, d.min(1 << 31));
        }
        check(-1, 3);
        check(5, 0x1_0000_0000);
    }

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
        let fx: FixedScene<2> = scene(&shapes, Vec3::new(0.0, 0.0, 1.0)).unwrap();
        assert!(fx.is_on());
        let (mut hits, mut differ) = (0, 0);
        for k in 0..200 {
            let a = k as f32 * 0.031;
            let dir = Vec3::new(a.sin() * 0.4, a.cos() * 0.3 - 0.2, -1.0).normalize();
            let ray = Ray { origin: Vec3::new(0.0, 0.0, 1.0), dir };
            for (i, s) in shapes.iter().enumerate() {
                let want = s.intersect(&ray, 0.0, f32::INFINITY);
                let got = fx.intersect(i, s, &ray, 0.0, f32::INFINITY);
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
            // The nearest of both, and the any-hit query, agree with the per-shape answers.
            let want = shapes
                .iter()
                .enumerate()
                .filter_map(|(i, s)| fx.intersect(i, s, &ray, 0.0, f32::INFINITY).map(|t| (t, i)))
                .fold(
                    None,
                    |b: Option<(f32, usize)>, h| if b.is_none_or(|b| h.0 < b.0) { Some(h) } else { b },
                );
            assert_eq!(fx.nearest(&shapes, &ray, 0.0, f32::INFINITY, false, |_| true), want);
            assert_eq!(
                fx.nearest(&shapes, &ray, 0.0, f32::INFINITY, true, |_| true).is_some(),
                want.is_some()
            );
        }
        assert!(hits > 100 && differ <= 2, "{hits} hits, {differ} differ");
    }

    /// A quad as large as the scene keeps its edges: rays aimed 1e-4 of its size inside or
    /// outside each edge hit or miss it as in f32 (with Q30 dual axes alone, a quad nearly as
    /// large as the scene reached past its far edges).
    #[test]
    fn large_quads_keep_their_edges() {
        let h = 3.0;
        let floor = Shape::quad([
            Vec3::new(-h, 0.0, -h),
            Vec3::new(-h, 0.0, h),
            Vec3::new(h, 0.0, h),
            Vec3::new(h, 0.0, -h),
        ])
        .unwrap();
        let eye = Vec3::new(0.1, 7.0, 0.2);
        let fx: FixedScene<1> = scene(&[floor], eye).unwrap();
        let mut checked = 0;
        for k in 0..64 {
            let along = -h + 2.0 * h * (k as f32 + 0.5) / 64.0;
            for off in [-6e-4f32, 6e-4] {
                let edge = h + off; // inside for off < 0
                for target in [
                    Vec3::new(edge, 0.0, along),
                    Vec3::new(-edge, 0.0, along),
                    Vec3::new(along, 0.0, edge),
                    Vec3::new(along, 0.0, -edge),
                ] {
                    let ray = Ray { origin: eye, dir: (target - eye).normalize() };
                    let want = floor.intersect(&ray, 0.0, f32::INFINITY);
                    assert_eq!(want.is_some(), off < 0.0, "the f32 test itself at {target}");
                    let got = fx.intersect(0, &floor, &ray, 0.0, f32::INFINITY);
                    assert_eq!(got.is_some(), want.is_some(), "at {target}");
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 512);
    }

    #[test]
    fn rays_outside_the_bounds_take_the_f32_test() {
        let shapes = [Shape::sphere(Vec3::new(0.0, 0.0, -3.0), 1.0).unwrap()];
        let fx: FixedScene<1> = scene(&shapes, Vec3::ZERO).unwrap();
        let ray = Ray { origin: Vec3::new(0.0, 0.0, 1e6), dir: Vec3::new(0.0, 0.0, -1.0) };
        assert_eq!(
            fx.intersect(0, &shapes[0], &ray, 0.0, f32::INFINITY),
            shapes[0].intersect(&ray, 0.0, f32::INFINITY)
        );
        let nan = Ray { origin: Vec3::new(f32::NAN, 0.0, 0.0), dir: Vec3::new(0.0, 0.0, -1.0) };
        assert_eq!(fx.nearest(&shapes, &nan, 0.0, f32::INFINITY, false, |_| true), None);
    }

    #[test]
    fn tiny_sphere_is_rejected_with_its_entry() {
        let shapes = [
            Shape::sphere(Vec3::new(0.0, 0.0, -3.0), 1.0).unwrap(),
            Shape::sphere(Vec3::new(0.0, 0.0, -100.0), 1e-4).unwrap(),
        ];
        let want = Err(SceneError::NotRepresentable { entry: 1, reason: Unrepresentable::TooSmall });
        assert_eq!(FixedScene::<2>::check(shapes.iter(), Vec3::ZERO), want);
        let mut fx: FixedScene<2> = FixedScene::off();
        assert_eq!(fx.turn_on(shapes.iter(), Vec3::ZERO), want);
        assert!(!fx.is_on() && fx.shapes.is_empty());
    }
}
