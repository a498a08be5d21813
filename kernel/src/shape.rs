//! Shapes: spheres and parallelograms ("quads"). Ray intersection, surface normals and uniform
//! area sampling. Both shapes are convex, so a ray leaving a surface on its front side never hits
//! that surface again: the estimator skips the shape of origin instead of nudging ray origins.

use crate::error::{Field, SceneError};
use crate::math::{PI, Vec2, Vec3, finite3, sqrt};
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

impl Quad {
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
        Ok(Shape::Sphere(Sphere { center, radius }))
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
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        match self {
            Shape::Sphere(s) => {
                // Numerically robust form (Haines et al., Ray Tracing Gems, ch. 7).
                let f = ray.origin - s.center;
                let b = f.dot(ray.dir);
                let l = f - ray.dir * b;
                let r2 = s.radius * s.radius;
                let disc = r2 - l.length_squared();
                if disc < 0.0 {
                    return None;
                }
                let c = f.length_squared() - r2;
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
            Shape::Quad(q) => {
                let denom = q.n.dot(ray.dir);
                if denom == 0.0 {
                    return None;
                }
                let t = (q.plane - q.n.dot(ray.origin)) / denom;
                if !(t > t_min && t < t_max) {
                    return None;
                }
                let d = ray.at(t) - q.p0;
                let s = d.dot(q.s_axis);
                let v = d.dot(q.t_axis);
                ((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&v)).then_some(t)
            }
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
}
