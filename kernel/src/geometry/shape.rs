//! Shapes: spheres and parallelograms ("quads"). Ray intersection, surface normals and uniform
//! area sampling. Both shapes are convex, so a ray leaving a surface on its front side never hits
//! that surface again: the estimator skips the shape of origin instead of nudging ray origins.

use crate::error::{Field, SceneError};
use crate::image::{Image, Words, float, vec3};
use crate::num::{PI, SOFT_FLOAT, Vec2, Vec3, dot, finite3, sqrt};
use crate::sampling::{parallelogram_pdf, sample_parallelogram, sample_uniform_sphere};

/// A ray with a unit direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Origin.
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
}

impl Ray {
    /// The point at distance `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// A point on a surface with its outward (front-side) unit normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Position.
    pub p: Vec3,
    /// Unit geometric normal of the front side.
    pub n: Vec3,
}

/// A sphere, front side outward.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    center: Vec3,
    radius: f32,
    /// `radius * radius`, as the intersection test squares it.
    r2: f32,
}

/// A parallelogram `p0 + s e1 + t e2`, (s, t) in [0, 1]^2, front side along `e1 x e2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quad {
    p0: Vec3,
    e1: Vec3,
    e2: Vec3,
    /// Unit normal.
    n: Vec3,
    /// `n . p0`: the plane is `n . x = plane`.
    plane: f32,
    /// Dual axes: `s = (x - p0) . s_axis`, `t = (x - p0) . t_axis` for a point `x` in the plane.
    s_axis: Vec3,
    t_axis: Vec3,
    area: f32,
}

/// The terms of a ray-shape test that depend on the ray's origin alone
/// ([`Shape::origin_terms`]): rays that share an origin (every camera ray; the shadow and BSDF
/// rays of one shading point) compute them once.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct OriginTerms(Terms);

impl OriginTerms {
    /// Terms that no shape's test reads as a hit (in place of those of an object the rays from
    /// an origin never test).
    pub(crate) const NONE: Self = OriginTerms(Terms::Quad { num: f32::NAN });
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Terms {
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
/// the reject runs ([`FIXED_REJECT`]), nothing ([`NoFixed`]) elsewhere (176 bytes of RAM on the
/// M4F's `RaysFrom` for the 11-object Veach scene).
#[cfg(any(test, all(target_os = "none", not(target_abi = "eabihf"), not(target_feature = "f"))))]
type SphereFixedTerms = SphereFixed;
#[cfg(not(any(test, all(target_os = "none", not(target_abi = "eabihf"), not(target_feature = "f")))))]
type SphereFixedTerms = NoFixed;

/// The empty stand-in for [`SphereFixed`] where [`FIXED_REJECT`] is off: it never rejects.
#[cfg_attr(
    any(test, all(target_os = "none", not(target_abi = "eabihf"), not(target_feature = "f"))),
    allow(dead_code)
)]
#[derive(Clone, Copy, Debug, PartialEq)]
struct NoFixed;

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
    fn rejects(&self, _d: &FixedDir, _t_min: f32) -> bool {
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
struct SphereFixed {
    gq: u32,
    /// In 16 bits (|q[i]| < 2^14): with `behind`'s spare values holding the enum's tag, the
    /// sphere's [`Terms`] take 8 words, which the compiler copies inline (44 bytes went through
    /// `memcpy`, about 70 instructions a copy on RV32IMC).
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
    fn rejects(&self, d: &FixedDir, t_min: f32) -> bool {
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

/// A rectangular quad in the form [`Shape::as_rectangle`] gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rectangle {
    /// A corner.
    pub p0: Vec3,
    /// Unit direction of the first edge from `p0`.
    pub ex: Vec3,
    /// Unit direction of the second edge, `n x ex`.
    pub ey: Vec3,
    /// Front normal.
    pub n: Vec3,
    /// Lengths of the edges along `ex` and `ey`.
    pub lengths: Vec2,
}

impl Sphere {
    /// The rest of the ray test from `f = o - center` and `b = f . d` on, with `c` giving
    /// `|f|^2 - r^2` (only needed when the line meets the sphere). Numerically robust form
    /// (Haines et al., Ray Tracing Gems, ch. 7).
    #[inline(always)]
    fn hit(
        &self,
        f: Vec3,
        b: f32,
        c: impl FnOnce() -> f32,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<f32> {
        let l = f - ray.dir * b;
        let disc = self.r2 - dot(l, l);
        if disc < 0.0 {
            return None;
        }
        let c = c();
        let q = -b - sqrt(disc).copysign(b);
        let (t0, t1) = if q != 0.0 { (c / q, q) } else { (0.0, 0.0) };
        let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        if near > t_min && near < t_max {
            Some(near)
        } else if far > t_min && far < t_max {
            Some(far)
        } else {
            None
        }
    }
}

impl Quad {
    /// The rest of the ray test from `num = plane - n . o` on, the hit distance's numerator.
    /// When `num` and the denominator `n . d` differ in sign, t = num / denom is negative or -0
    /// (a NaN `num` gives a NaN t), never above a t_min >= +0: that case skips the division
    /// (an exact early reject). A zero `denom` needs no test of its own: t is then +inf, -inf
    /// or NaN, which `hit_at`'s `t > t_min && t < t_max` rejects for every t_min and t_max.
    #[inline(always)]
    fn hit(&self, num: f32, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let denom = dot(self.n, ray.dir);
        if num.is_sign_negative() != denom.is_sign_negative() && !t_min.is_sign_negative() {
            return None;
        }
        self.hit_at(num / denom, ray, t_min, t_max)
    }

    /// The end of the ray test: the plane is met at distance `t`; is it in range, and the point
    /// inside?
    #[inline(always)]
    fn hit_at(&self, t: f32, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        if !(t > t_min && t < t_max) {
            return None;
        }
        let d = ray.at(t) - self.p0;
        let s = dot(d, self.s_axis);
        let v = dot(d, self.t_axis);
        ((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&v)).then_some(t)
    }

    /// Corner `p0` and the edges `e1`, `e2` (for the fixed-point path, `kernel/src/fixed.rs`).
    #[cfg(feature = "fixed")]
    pub(crate) fn edges(&self) -> (Vec3, Vec3, Vec3) {
        (self.p0, self.e1, self.e2)
    }

    /// Unit normal, plane offset `n . p0`, corner `p0`, and the dual axes.
    #[cfg_attr(target_os = "none", allow(dead_code))]
    pub(crate) fn parts(&self) -> (Vec3, f32, Vec3, Vec3, Vec3) {
        (self.n, self.plane, self.p0, self.s_axis, self.t_axis)
    }
}

/// The closed set of shapes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A sphere.
    Sphere(Sphere),
    /// A parallelogram.
    Quad(Quad),
}

/// Relative tolerance for "p2 = p1 + p3 - p0" in [`Shape::quad`] (as in the scene format).
pub const PARALLELOGRAM_TOLERANCE: f32 = 1e-5;

impl Shape {
    /// A sphere; the center must be finite and the radius finite and positive.
    pub fn sphere(center: Vec3, radius: f32) -> Result<Self, SceneError> {
        if !finite3(center) {
            return Err(SceneError::NonFinite(Field::Center));
        }
        if !radius.is_finite() {
            return Err(SceneError::NonFinite(Field::Radius));
        }
        if radius <= 0.0 {
            return Err(SceneError::NonPositive(Field::Radius));
        }
        Ok(Shape::Sphere(Sphere { center, radius, r2: radius * radius }))
    }

    /// A parallelogram from its four corners in order (`p2` must equal `p1 + p3 - p0`).
    pub fn quad(p: [Vec3; 4]) -> Result<Self, SceneError> {
        let [p0, p1, p2, p3] = p;
        if !p.iter().all(|&v| finite3(v)) {
            return Err(SceneError::NonFinite(Field::Corner));
        }
        let (e1, e2) = (p1 - p0, p3 - p0);
        let scale = e1.length().max(e2.length()).max(p0.abs().max_element());
        if (p1 + p3 - p0 - p2).length() > PARALLELOGRAM_TOLERANCE * scale.max(f32::MIN_POSITIVE) {
            return Err(SceneError::NotParallelogram);
        }
        let c = e1.cross(e2);
        let area = c.length();
        let len2 = c.length_squared();
        if !(area > 0.0) || !area.is_finite() || !(len2 > 0.0) || !len2.is_finite() {
            return Err(SceneError::DegenerateQuad);
        }
        // Reject slivers whose normal is lost to rounding.
        if area <= 1e-6 * e1.length() * e2.length() {
            return Err(SceneError::DegenerateQuad);
        }
        // With w = c / |c|^2: s = (d x e2) . w = d . (e2 x w), t = (e1 x d) . w = d . (w x e1).
        let w = c / len2;
        let n = c / area;
        Ok(Shape::Quad(Quad {
            p0,
            e1,
            e2,
            n,
            plane: n.dot(p0),
            s_axis: e2.cross(w),
            t_axis: w.cross(e1),
            area,
        }))
    }

    /// Surface area.
    #[inline]
    pub fn area(&self) -> f32 {
        match self {
            Shape::Sphere(s) => 4.0 * PI * s.radius * s.radius,
            Shape::Quad(q) => q.area,
        }
    }

    /// Distance to the nearest hit in `(t_min, t_max)`, either side of the surface.
    #[inline(never)]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        self.intersect_inlined(ray, t_min, t_max)
    }

    /// [`Shape::intersect`], inlined into the loops of the ray queries.
    #[inline(always)]
    pub(crate) fn intersect_inlined(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        match self {
            Shape::Sphere(s) => {
                let f = ray.origin - s.center;
                s.hit(f, dot(f, ray.dir), || dot(f, f) - s.r2, ray, t_min, t_max)
            }
            Shape::Quad(q) => q.hit(q.plane - dot(q.n, ray.origin), ray, t_min, t_max),
        }
    }

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

    /// The front-side unit normal at a point on the surface.
    #[inline]
    pub fn normal_at(&self, p: Vec3) -> Vec3 {
        match self {
            Shape::Sphere(s) => (p - s.center) / s.radius,
            Shape::Quad(q) => q.n,
        }
    }

    /// A uniformly distributed point on the surface; its pdf is [`Shape::area_pdf`].
    #[inline]
    pub fn sample_area(&self, u: Vec2) -> SurfacePoint {
        match self {
            Shape::Sphere(s) => {
                let n = sample_uniform_sphere(u);
                SurfacePoint { p: s.center + n * s.radius, n }
            }
            Shape::Quad(q) => {
                let st = sample_parallelogram(u);
                SurfacePoint { p: q.p0 + q.e1 * st.x + q.e2 * st.y, n: q.n }
            }
        }
    }

    /// Pdf of [`Shape::sample_area`] per unit area.
    #[inline]
    pub fn area_pdf(&self) -> f32 {
        parallelogram_pdf(self.area())
    }

    /// The sphere's center and radius, if this is a sphere.
    #[inline]
    pub fn as_sphere(&self) -> Option<(Vec3, f32)> {
        match self {
            Shape::Sphere(s) => Some((s.center, s.radius)),
            Shape::Quad(_) => None,
        }
    }

    /// A quad whose edges are perpendicular (to 1e-5 of their lengths' product), as its corner
    /// `p0`, unit edge directions `ex` and `ey = n x ex` (a right-handed frame with the front
    /// normal `n`), and edge lengths: what sampling in solid angle needs.
    #[inline]
    pub fn as_rectangle(&self) -> Option<Rectangle> {
        match self {
            Shape::Sphere(_) => None,
            Shape::Quad(q) => {
                let (l1, l2) = (sqrt(q.e1.length_squared()), sqrt(q.e2.length_squared()));
                let perpendicular = q.e1.dot(q.e2).abs() <= 1e-5 * l1 * l2;
                if !(perpendicular && l1 > 0.0 && l2 > 0.0) {
                    return None;
                }
                let ex = q.e1 / l1;
                Some(Rectangle { p0: q.p0, ex, ey: q.n.cross(ex), n: q.n, lengths: Vec2::new(l1, l2) })
            }
        }
    }

    /// A quad's four corners `p0, p0 + e1, p0 + e1 + e2, p0 + e2` (front side along e1 x e2).
    #[inline]
    pub fn corners(&self) -> Option<[Vec3; 4]> {
        match self {
            Shape::Sphere(_) => None,
            Shape::Quad(q) => Some([q.p0, q.p0 + q.e1, q.p0 + q.e1 + q.e2, q.p0 + q.e2]),
        }
    }

    /// Radius of a sphere around [`Shape::centroid`] that holds the shape.
    #[inline]
    pub fn bounding_radius(&self) -> f32 {
        match self {
            Shape::Sphere(s) => s.radius,
            Shape::Quad(q) => 0.5 * (q.e1 + q.e2).length().max((q.e1 - q.e2).length()),
        }
    }

    /// A point the shape surrounds or lies on (sphere center, quad centroid).
    #[inline]
    pub fn centroid(&self) -> Vec3 {
        match self {
            Shape::Sphere(s) => s.center,
            Shape::Quad(q) => q.p0 + (q.e1 + q.e2) * 0.5,
        }
    }
}

impl Image for Shape {
    fn put(&self, out: &mut dyn FnMut(u32)) {
        match self {
            Shape::Sphere(s) => {
                out(0);
                s.center.put(out);
                s.radius.put(out);
                s.r2.put(out);
            }
            Shape::Quad(q) => {
                out(1);
                for v in [q.p0, q.e1, q.e2, q.n, q.s_axis, q.t_axis] {
                    v.put(out);
                }
                q.plane.put(out);
                q.area.put(out);
            }
        }
    }
    fn get(w: &mut Words<'_>) -> Option<Self> {
        Some(match w.u32()? {
            0 => {
                let a: [u32; 5] = w.take()?;
                Shape::Sphere(Sphere { center: vec3(&a, 0), radius: float(&a, 3), r2: float(&a, 4) })
            }
            1 => {
                let a: [u32; 20] = w.take()?;
                Shape::Quad(Quad {
                    p0: vec3(&a, 0),
                    e1: vec3(&a, 3),
                    e2: vec3(&a, 6),
                    n: vec3(&a, 9),
                    s_axis: vec3(&a, 12),
                    t_axis: vec3(&a, 15),
                    plane: float(&a, 18),
                    area: float(&a, 19),
                })
            }
            _ => return None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn construction_rejects_bad_values() {
        assert_eq!(Shape::sphere(Vec3::ZERO, 0.0), Err(SceneError::NonPositive(Field::Radius)));
        assert_eq!(Shape::sphere(Vec3::ZERO, -1.0), Err(SceneError::NonPositive(Field::Radius)));
        assert_eq!(
            Shape::sphere(Vec3::new(f32::NAN, 0.0, 0.0), 1.0),
            Err(SceneError::NonFinite(Field::Center))
        );
        assert_eq!(Shape::sphere(Vec3::ZERO, f32::INFINITY), Err(SceneError::NonFinite(Field::Radius)));
        let z = Vec3::ZERO;
        assert_eq!(Shape::quad([z, z, z, z]), Err(SceneError::DegenerateQuad));
        assert_eq!(Shape::quad([z, Vec3::X, Vec3::X * 2.0, Vec3::X]), Err(SceneError::DegenerateQuad));
        assert_eq!(
            Shape::quad([z, Vec3::X, Vec3::new(1.0, 1.5, 0.0), Vec3::Y]),
            Err(SceneError::NotParallelogram)
        );
    }

    #[test]
    fn quad_hits_inside_only_from_both_sides() {
        let q = Shape::quad([Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y]).unwrap();
        assert!((q.area() - 1.0).abs() < 1e-6);
        assert_eq!(q.normal_at(Vec3::ZERO), Vec3::Z);
        let down = Ray { origin: Vec3::new(0.5, 0.5, 1.0), dir: -Vec3::Z };
        assert_eq!(q.intersect(&down, 0.0, 10.0), Some(1.0));
        let up = Ray { origin: Vec3::new(0.5, 0.5, -2.0), dir: Vec3::Z };
        assert_eq!(q.intersect(&up, 0.0, 10.0), Some(2.0));
        let miss = Ray { origin: Vec3::new(1.5, 0.5, 1.0), dir: -Vec3::Z };
        assert_eq!(q.intersect(&miss, 0.0, 10.0), None);
        assert_eq!(q.intersect(&down, 0.0, 0.5), None);
    }

    #[test]
    fn rays_parallel_to_a_quad_never_hit_it() {
        // n . d = +-0: t = num / denom is +-inf or NaN, which no distance range admits.
        let q = Shape::quad([Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y]).unwrap();
        for z in [1.0, 0.0, -0.0, -1.0] {
            for dir in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y] {
                let ray = Ray { origin: Vec3::new(0.5, 0.5, z), dir };
                for (t_min, t_max) in [(0.0, f32::INFINITY), (f32::NEG_INFINITY, f32::INFINITY), (-0.0, 10.0)]
                {
                    assert_eq!(q.intersect(&ray, t_min, t_max), None, "z {z} dir {dir} t {t_min} {t_max}");
                }
            }
        }
    }

    #[test]
    fn sphere_hits_near_then_far_and_tiny_spheres_are_found() {
        let s = Shape::sphere(Vec3::new(0.0, 0.0, -5.0), 1.0).unwrap();
        let r = Ray { origin: Vec3::ZERO, dir: -Vec3::Z };
        assert_eq!(s.intersect(&r, 0.0, 100.0), Some(4.0));
        assert_eq!(s.intersect(&r, 4.5, 100.0), Some(6.0));
        let inside = Ray { origin: Vec3::new(0.0, 0.0, -5.0), dir: Vec3::X };
        assert_eq!(s.intersect(&inside, 0.0, 100.0), Some(1.0));
        let tiny = Shape::sphere(Vec3::new(0.0, 0.0, -1.0), 1e-6).unwrap();
        let t = tiny.intersect(&r, 0.0, 100.0).unwrap();
        assert!((t - 1.0).abs() < 1e-5);
    }

    /// `Shape::intersect` as it was before the early rejects: the reference they must match.
    /// (Its sphere test has none; a quad's is the test without the sign reject.)
    fn intersect_without_rejects(shape: &Shape, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        match shape {
            Shape::Sphere(_) => shape.intersect(ray, t_min, t_max),
            Shape::Quad(q) => {
                let denom = q.n.dot(ray.dir);
                if denom == 0.0 {
                    return None;
                }
                q.hit_at((q.plane - q.n.dot(ray.origin)) / denom, ray, t_min, t_max)
            }
        }
    }

    /// How often each early reject fired, and the near calls around them.
    #[derive(Debug, Default)]
    struct RejectCounts {
        far_line: u32,
        behind: u32,
        quad_behind: u32,
        /// Misses the far-line reject let through (the margin at work).
        missed_in_margin: u32,
        /// Rays the fixed-point reject rejected.
        fixed: u32,
        /// Hits whose discriminant is within 1e-3 r^2 of zero (grazing rays).
        grazing_hits: u32,
    }

    fn unit(rng: &mut crate::sampling::sampler::Sampler) -> Vec3 {
        crate::sampling::sample_uniform_sphere(rng.next_2d())
    }

    /// A random number in [-a, a] with a log-uniform magnitude in [a 2^-40, a].
    fn spread(rng: &mut crate::sampling::sampler::Sampler, a: f32) -> f32 {
        let m = a / f32::from_bits((127 + (rng.next_u32() % 40)) << 23);
        if rng.next_u32() & 1 == 0 { m } else { -m }
    }

    /// Rays built to graze, start on, inside or near the shape, or go anywhere, against the
    /// test without the rejects: the same bits every time.
    #[test]
    fn early_rejects_never_change_a_result() {
        let mut rng = crate::sampling::sampler::Sampler::new(11, 0, 0);
        let mut n = RejectCounts::default();
        let mut hits = 0u32;
        for case in 0..8000 {
            let point = |rng: &mut crate::sampling::sampler::Sampler, a: f32| {
                Vec3::new(rng.next_f32() * 2.0 - 1.0, rng.next_f32() * 2.0 - 1.0, rng.next_f32() * 2.0 - 1.0)
                    * a
            };
            let scale = f32::from_bits((127 + (rng.next_u32() % 24) - 12) << 23);
            let shape = if case % 2 == 0 {
                let r = scale * (0.001 + rng.next_f32());
                Shape::sphere(point(&mut rng, 2.0 * scale), r).unwrap()
            } else {
                let (p0, e1, e2) =
                    (point(&mut rng, 2.0 * scale), point(&mut rng, scale), point(&mut rng, scale));
                match Shape::quad([p0, p0 + e1, p0 + e1 + e2, p0 + e2]) {
                    Ok(q) => q,
                    Err(_) => continue,
                }
            };
            let (centre, extent) = (shape.centroid(), shape.bounding_radius());
            for _ in 0..100 {
                let origin = match rng.next_u32() % 4 {
                    0 => centre + point(&mut rng, 8.0 * extent),
                    // On the surface (as a shading point is), or just off it.
                    1 => {
                        shape.sample_area(rng.next_2d()).p + unit(&mut rng) * spread(&mut rng, extent * 1e-3)
                    }
                    2 => centre + point(&mut rng, 0.5 * extent),
                    _ => centre + unit(&mut rng) * extent * (1.0 + spread(&mut rng, 4.0)),
                };
                let target = match (rng.next_u32() % 3, shape.as_sphere()) {
                    // Just inside or outside the silhouette: a grazing ray.
                    (0, Some((c, r))) => {
                        let axis = crate::num::normalize_or(c - origin, Vec3::X);
                        let side = crate::num::normalize_or(axis.cross(unit(&mut rng)), Vec3::Y);
                        c + side * r * (1.0 + spread(&mut rng, 1e-2))
                    }
                    (0, None) => {
                        shape.sample_area(rng.next_2d()).p + unit(&mut rng) * spread(&mut rng, extent)
                    }
                    (1, _) => centre + unit(&mut rng) * extent * rng.next_f32(),
                    _ => origin + unit(&mut rng),
                };
                let Some(dir) = crate::num::try_normalize(target - origin) else { continue };
                let ray = Ray { origin, dir };
                let t_min = match rng.next_u32() % 6 {
                    0 => -0.0,
                    1 => -extent * rng.next_f32(),
                    2 => extent * rng.next_f32(),
                    _ => 0.0,
                };
                let t_max =
                    if rng.next_u32() & 1 == 0 { f32::INFINITY } else { 4.0 * extent * rng.next_f32() };
                let want = intersect_without_rejects(&shape, &ray, t_min, t_max);
                let bits = |t: Option<f32>| t.map(f32::to_bits);
                let got = shape.intersect(&ray, t_min, t_max);
                assert_eq!(bits(got), bits(want), "{shape:?} {ray:?} {t_min} {t_max}");
                let terms = shape.origin_terms(origin);
                let fixed_dir = FixedDir::new(dir);
                let got = shape.intersect_from(&terms, &ray, &fixed_dir, t_min, t_max);
                assert_eq!(bits(got), bits(want), "from terms: {shape:?} {ray:?} {t_min} {t_max}");
                hits += u32::from(want.is_some());
                let positive = !t_min.is_sign_negative();
                match (shape, terms.0) {
                    (Shape::Sphere(s), Terms::Sphere { f, c, g, fixed }) => {
                        let b = f.dot(dir);
                        if fixed.rejects(&fixed_dir, t_min) {
                            // What the proof says: one of the f32 rejects fires too.
                            assert!(b * b < g || (b > 0.0 && c > 0.0 && positive), "{shape:?} {ray:?}");
                            n.fixed += 1;
                        }
                        let disc = s.r2 - (f - dir * b).length_squared();
                        if b * b < g {
                            n.far_line += 1;
                        } else if disc < 0.0 {
                            n.missed_in_margin += 1;
                        } else if b > 0.0 && c > 0.0 && positive {
                            n.behind += 1;
                        }
                        if want.is_some() && disc < 1e-3 * s.r2 {
                            n.grazing_hits += 1;
                        }
                    }
                    (Shape::Quad(q), Terms::Quad { num }) => {
                        let denom = q.n.dot(dir);
                        if denom != 0.0 && num.is_sign_negative() != denom.is_sign_negative() && positive {
                            n.quad_behind += 1;
                        }
                    }
                    _ => unreachable!("terms of the shape's own kind"),
                }
            }
        }
        // Not vacuous: every reject fired often, rays came close to its boundary, many hit.
        assert!(n.far_line > 30_000 && n.behind > 5_000 && n.quad_behind > 50_000, "{n:?}");
        // The integer reject catches nearly all that the f32 rejects do.
        assert!(n.fixed > (n.far_line + n.behind) * 99 / 100, "{n:?}");
        assert!(n.missed_in_margin > 300 && n.grazing_hits > 1_000, "{n:?}");
        assert!(hits > 100_000, "{hits}");
    }
}
