//! Shapes: spheres and parallelograms ("quads"). Ray intersection, surface normals and uniform
//! area sampling. Both shapes are convex, so a ray leaving a surface on its front side never hits
//! that surface again: the estimator skips the shape of origin instead of nudging ray origins.

use crate::error::{Field, SceneError};
use crate::num::{PI, Vec2, Vec3, dot, finite3, sqrt};
use crate::sampling::{parallelogram_pdf, sample_parallelogram, sample_uniform_sphere};
use crate::words::{Image, Words, float, vec3};

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
    pub(super) center: Vec3,
    radius: f32,
    /// `radius * radius`, as the intersection test squares it.
    pub(super) r2: f32,
}

/// A parallelogram `p0 + s e1 + t e2`, (s, t) in [0, 1]^2, front side along `e1 x e2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quad {
    p0: Vec3,
    e1: Vec3,
    e2: Vec3,
    /// Unit normal.
    pub(super) n: Vec3,
    /// `n . p0`: the plane is `n . x = plane`.
    pub(super) plane: f32,
    /// Dual axes: `s = (x - p0) . s_axis`, `t = (x - p0) . t_axis` for a point `x` in the plane.
    s_axis: Vec3,
    t_axis: Vec3,
    area: f32,
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
    pub(super) fn hit(
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
    pub(super) fn hit(&self, num: f32, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
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

    /// Corner `p0` and the edges `e1`, `e2` (for the fixed-point path, `kernel/src/query/fixed.rs`).
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

    /// The squared extent of the shape (a quad's diagonal, a sphere's diameter) and its centre.
    #[inline]
    fn extent2_and_centre(&self) -> (f32, Vec3) {
        match self {
            Shape::Sphere(s) => (4.0 * s.radius * s.radius, s.center),
            Shape::Quad(q) => {
                let diagonal = q.e1 + q.e2;
                (diagonal.length_squared(), q.p0 + diagonal * 0.5)
            }
        }
    }

    /// Whether the shape looks small from `x`: its extent (a quad's diagonal, a sphere's
    /// diameter) is shorter than `ratio` times the distance from `x` to its centre.
    #[inline]
    pub fn looks_small(&self, x: Vec3, ratio: f32) -> bool {
        let (extent2, centre) = self.extent2_and_centre();
        extent2 < ratio * ratio * (centre - x).length_squared()
    }

    /// Whether the shape looks small and steep from a receiver at `x` with unit normal `n`: its
    /// extent is shorter than `ratio` times the height of its centre above the receiver's plane,
    /// and for a quad also than `ratio` times the height of `x` above the quad's plane. Over such
    /// a shape the distance and both cosines (the receiver's, the quad's) hardly vary.
    #[inline]
    pub fn looks_small_and_steep(&self, x: Vec3, n: Vec3, ratio: f32) -> bool {
        let (extent2, centre) = self.extent2_and_centre();
        let facing = match self {
            Shape::Sphere(_) => f32::INFINITY,
            Shape::Quad(q) => q.n.dot(x - centre),
        };
        let height = n.dot(centre - x).min(facing);
        height > 0.0 && extent2 < ratio * ratio * height * height
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
    use crate::geometry::terms::{FixedDir, Terms};

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
