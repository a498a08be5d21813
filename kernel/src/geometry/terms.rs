//! The terms of a ray-shape test that depend on the ray's origin alone: rays that share an
//! origin (every camera ray; the shadow and BSDF rays of one shading point) compute them once,
//! with the early rejects they make cheap.

use crate::geometry::shape::{Ray, Shape};
use crate::num::{SOFT_FLOAT, Vec3, dot};

/// The terms of a ray-shape test that depend on the ray's origin alone
/// ([`Shape::origin_terms`]): rays that share an origin (every camera ray; the shadow and BSDF
/// rays of one shading point) compute them once.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct OriginTerms(pub(super) Terms);

impl OriginTerms {
    /// Terms that no shape's test reads as a hit (in place of those of an object the rays from
    /// an origin never test).
    pub(crate) const NONE: Self = OriginTerms(Terms::Quad { num: f32::NAN });
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Terms {
    /// `f = o - center`, `c = |f|^2 - r^2`, the bound `g` of the early reject, and the
    /// integer copies of the fixed-point reject.
    Sphere { f: Vec3, c: f32, g: f32, fixed: SphereFixedTerms },
    /// `plane - n . o`: the hit distance's numerator.
    Quad { num: f32 },
}

/// The early sphere reject's margin, relative to |f|^2 (see [`Shape::intersect_from`]).
const REJECT_MARGIN: f32 = 1.0 / 4096.0;
/// Below this |f|^2 (2^-60) the sphere reject is off: rounding there need not be relative.
const REJECT_MIN_F2: f32 = f32::from_bits((127 - 60) << 23);

/// Whether the sphere test runs the fixed-point reject ([`SphereFixed`]) first: where f32
/// operations are soft-float calls (a dozen integer instructions against five calls), and in the
/// kernel's unit tests, which check it.
const FIXED_REJECT: bool = SOFT_FLOAT || cfg!(test);

/// What a sphere's origin terms store for the fixed-point reject: its [`SphereFixed`] terms where
/// the reject runs ([`FIXED_REJECT`]), nothing ([`NoFixed`]) elsewhere (no RAM in `RaysFrom`
/// on the cores with an FPU).
#[cfg(any(test, all(target_os = "none", not(target_abi = "eabihf"), not(target_feature = "f"))))]
pub(super) type SphereFixedTerms = SphereFixed;
#[cfg(not(any(test, all(target_os = "none", not(target_abi = "eabihf"), not(target_feature = "f")))))]
pub(super) type SphereFixedTerms = NoFixed;

/// The empty stand-in for [`SphereFixed`] where [`FIXED_REJECT`] is off: it never rejects.
#[cfg_attr(
    any(test, all(target_os = "none", not(target_abi = "eabihf"), not(target_feature = "f"))),
    allow(dead_code)
)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct NoFixed;

#[cfg_attr(
    any(test, all(target_os = "none", not(target_abi = "eabihf"), not(target_feature = "f"))),
    allow(dead_code)
)]
impl NoFixed {
    const OFF: Self = Self;

    #[inline(always)]
    fn new(_f: Vec3, _g: f32, _c: f32) -> Self {
        Self
    }

    #[inline(always)]
    pub(super) fn rejects(&self, _d: &FixedDir, _t_min: f32) -> bool {
        false
    }
}

/// A ray direction in fixed point for the integer rejects: `q[i] = trunc(d[i] * 2^14)`
/// (|d[i]| < 2, so |q[i]| < 2^15); `ok` is false for a direction with a component that is not
/// below 2 in magnitude (or not finite), which the rejects let through.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FixedDir {
    q: [i32; 3],
    ok: bool,
}

impl FixedDir {
    /// The fixed-point copy of the direction `d` (computed once per ray, with integer
    /// instructions only).
    #[cfg_attr(not(target_os = "none"), allow(dead_code))]
    #[inline]
    pub(crate) fn new(d: Vec3) -> Self {
        if !FIXED_REJECT {
            return Self { q: [0; 3], ok: false };
        }
        let ok = [d.x, d.y, d.z].iter().all(|v| exponent(*v) <= 127);
        if !ok {
            return Self { q: [0; 3], ok: false };
        }
        Self { q: [fixed(d.x, 136), fixed(d.y, 136), fixed(d.z, 136)], ok }
    }
}

/// The biased exponent field of `x` (1 for subnormals and zeros, which are `m * 2^(1 - 150)`).
#[inline(always)]
fn exponent(x: f32) -> i32 {
    (((x.to_bits() >> 23) & 0xff) as i32).max(1)
}

/// `trunc(x * 2^(150 - base))` from the bits of `x`, for `base - exponent(x)` in 0..; 0 when
/// that shift is 32 or more. Exact up to the truncation: |result - x 2^(150 - base)| < 1.
#[inline(always)]
fn fixed(x: f32, base: i32) -> i32 {
    let bits = x.to_bits();
    let e = (bits >> 23) & 0xff;
    let m = (bits & 0x7f_ffff) | if e != 0 { 0x80_0000 } else { 0 };
    let q = match u32::try_from(base - exponent(x)) {
        Ok(s) if s < 32 => (m >> s) as i32,
        _ => 0,
    };
    if bits >> 31 != 0 { -q } else { q }
}

/// Bound on |Bi - b 2^(14-k)| (see [`SphereFixed`]): quantization 3 (2^14 + 2^15), the f32 dot
/// product's own error 3u/(1-3u) * 3 * 2^29 < 300, rounded up.
const FIXED_DOT_ERROR: i32 = 148_000;

/// The sphere's terms for the fixed-point reject, from the origin: `f` scaled by `2^-k` to
/// `q[i] = trunc(f[i] 2^-k)` (|q[i]| < 2^14, k from the largest exponent of `f`), the bound
/// `gq <= g 2^(-2k-2) / (1 + 2^-20)` (0: no far-line reject), and `behind`: c > 0.
///
/// With `Bi = q . dq` (the direction's [`FixedDir`]), the f32 `b = f . d` the full test computes
/// satisfies |b 2^(14-k) - Bi| <= [`FIXED_DOT_ERROR`] = E: each product is off by less than
/// |f[i] 2^-k| + |dq[i]| < 2^14 + 2^15 from the exact f[i] 2^-k d[i] 2^14, and the f32 dot
/// product by at most 3u/(1-3u) sum |f[i] d[i]| from the exact one. So
/// - with X = ((|Bi| + E) >> 15) + 1: |b| < X 2^(k+1), and X^2 < gq gives
///   b^2 (1 + 2^-20) < g: the computed b * b (correctly rounded; below 2^-126 when it is not
///   normal, and g >= 2^-100 here) is below g, which is the f32 far-line reject of
///   [`Shape::intersect_from`];
/// - Bi > E gives b > 0, which with c > 0 and t_min >= +0 is its exact behind-the-origin reject.
///
/// Either way the full test would reject the ray: the result is the same, bit for bit.
#[cfg_attr(
    not(any(test, all(target_os = "none", not(target_abi = "eabihf"), not(target_feature = "f")))),
    allow(dead_code)
)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SphereFixed {
    gq: u32,
    /// In 16 bits (|q[i]| < 2^14): with `behind`'s spare values holding the enum's tag, the
    /// sphere's [`Terms`] take 8 words, which the compiler copies inline (11 words would go
    /// through `memcpy` on RV32IMC).
    q: [i16; 3],
    behind: bool,
}

#[cfg_attr(
    not(any(test, all(target_os = "none", not(target_abi = "eabihf"), not(target_feature = "f")))),
    allow(dead_code)
)]
impl SphereFixed {
    const OFF: Self = Self { gq: 0, q: [0; 3], behind: false };

    /// The terms for `f`, the f32 reject bound `g` and `c`.
    #[inline(always)]
    fn new(f: Vec3, g: f32, c: f32) -> Self {
        let emax = exponent(f.x).max(exponent(f.y)).max(exponent(f.z));
        if emax == 255 {
            return Self::OFF; // not finite
        }
        // k = emax - 140: |f[i]| < 2^(emax - 126), so |f[i] 2^-k| < 2^14.
        let k = emax - 140;
        let base = 150 + k;
        // |fixed(.)| < 2^14: the casts are exact.
        let q = [fixed(f.x, base) as i16, fixed(f.y, base) as i16, fixed(f.z, base) as i16];
        // gq from the bits of g = mg 2^(eg - 150) >= 2^-100 (else 0).
        let gb = g.to_bits();
        let gq = if (0x0d80_0000..0x7f80_0000).contains(&gb) {
            let eg = (gb >> 23) as i32;
            let mg = (gb & 0x7f_ffff) | 0x80_0000;
            // V = g 2^(-2k-2) = mg 2^p.
            let p = eg - 150 - 2 * k - 2;
            let v = if p >= 9 {
                u32::MAX // V >= 2^32: above any X^2 (X < 2^16), even with the margin
            } else if p >= 0 {
                mg << p
            } else if p > -32 {
                mg >> -p
            } else {
                0
            };
            // The margin: v - v 2^-19 <= V / (1 + 2^-20).
            v.saturating_sub((v >> 19) + 1)
        } else {
            0
        };
        // c > 0 (false for NaN), from the bits.
        let cb = c.to_bits() as i32;
        let behind = cb > 0 && cb <= 0x7f80_0000;
        Self { gq, q, behind }
    }

    /// Whether the integer test proves the full test rejects the ray with this direction
    /// (see the type's docs).
    #[inline(always)]
    pub(super) fn rejects(&self, d: &FixedDir, t_min: f32) -> bool {
        if !d.ok {
            return false;
        }
        let [a, b, c] = self.q.map(i32::from);
        let [x, y, z] = d.q;
        // |a x| < 2^29: the sum of three stays below 2^31.
        let bi = a * x + b * y + c * z;
        let m = (bi.unsigned_abs() + FIXED_DOT_ERROR as u32) >> 15;
        let m = m + 1;
        m * m < self.gq || (bi > FIXED_DOT_ERROR && self.behind && !t_min.is_sign_negative())
    }
}

impl Shape {
    /// The terms of [`Shape::intersect`] that depend on the ray's origin alone, for
    /// [`Shape::intersect_from`].
    #[inline]
    pub(crate) fn origin_terms(&self, origin: Vec3) -> OriginTerms {
        OriginTerms(match self {
            Shape::Sphere(s) => {
                let f = origin - s.center;
                let f2 = dot(f, f);
                let c = f2 - s.r2;
                // The bound of the early reject (see `intersect_from`); 0 rejects nothing.
                let g = if f2 >= REJECT_MIN_F2 { c - f2 * REJECT_MARGIN } else { 0.0 };
                let fixed = if FIXED_REJECT { SphereFixedTerms::new(f, g, c) } else { SphereFixedTerms::OFF };
                Terms::Sphere { f, c, g, fixed }
            }
            Shape::Quad(q) => Terms::Quad { num: q.plane - dot(q.n, origin) },
        })
    }

    /// [`Shape::intersect`] with the terms `self.origin_terms(ray.origin)` computed beforehand
    /// (once for all the rays from one origin), and, for spheres, two early rejects they make
    /// cheap; terms of another shape give `None`.
    ///
    /// The rejects only ever reject rays the full test would reject too, so the result is that
    /// of [`Shape::intersect`], bit for bit (u = 2^-24, and the direction is a unit vector:
    /// | |d|^2 - 1 | <= 2^-16):
    /// - **the line passes far from the centre** (conservative): `b * b < g` with
    ///   g = c - 2^-12 |f|^2 gives b^2 < |f|^2 - r^2 - (2^-12 - 9u) |f|^2. The dot product's
    ///   error |b - f.d| <= 3u |f| |d| then puts the line's squared distance to the centre,
    ///   |f|^2 - (f.d)^2 / |d|^2, above r^2 + (2^-12 - 2^-15 - 16u) |f|^2, and the computed
    ///   |l|^2 (each component off by at most u (|d b| + |l|)) stays above r^2: the full test's
    ///   disc = r^2 - |l|^2 is negative. Below |f|^2 = 2^-60 (where rounding of subnormals is
    ///   not relative) and for non-finite terms (g NaN) it rejects nothing;
    /// - **the sphere lies behind the origin** (exact): with b > 0 the full test computes
    ///   q = -b - sqrt(disc) <= -b < 0 (rounding is monotonic), so t1 = q < 0, and
    ///   t0 = c / q <= -0 when c > 0: neither exceeds a t_min >= +0.
    ///
    /// Before them, where [`FIXED_REJECT`] says so, the integer reject of [`SphereFixed`] (with
    /// `dir`, the fixed-point copy of `ray.dir`) proves one of the two fires, in a dozen integer
    /// instructions: it too never changes a result.
    ///
    /// `shape::tests` checks them against the test without them on random rays.
    #[cfg_attr(not(target_os = "none"), allow(dead_code))]
    #[inline(always)]
    pub(crate) fn intersect_from(
        &self,
        terms: &OriginTerms,
        ray: &Ray,
        dir: &FixedDir,
        t_min: f32,
        t_max: f32,
    ) -> Option<f32> {
        match (self, &terms.0) {
            (Shape::Sphere(s), &Terms::Sphere { f, c, g, ref fixed }) => {
                if FIXED_REJECT && fixed.rejects(dir, t_min) {
                    return None;
                }
                let b = dot(f, ray.dir);
                if b * b < g || (b > 0.0 && c > 0.0 && !t_min.is_sign_negative()) {
                    return None;
                }
                s.hit(f, b, || c, ray, t_min, t_max)
            }
            (Shape::Quad(q), &Terms::Quad { num }) => q.hit(num, ray, t_min, t_max),
            _ => None,
        }
    }
}
