//! The pinhole camera of the scene format: film coordinates (u right, v down) in [0, 1]^2,
//! a vertical or horizontal field of view, and a near clip plane.

use crate::error::{Field, SceneError};
use crate::geometry::shape::Ray;
use crate::num::{Vec2, Vec3, dot, finite3, positive_finite, sin_cos_turns, sqrt, try_normalize};
use crate::words::{Image, Words, float, vec3};

/// Which film axis the field of view spans.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FovAxis {
    /// Horizontal.
    X,
    /// Vertical.
    Y,
}

/// Film resolution in pixels (1 to 16384 per side).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Film {
    width: u16,
    height: u16,
}

/// Largest film side.
pub const MAX_FILM_SIDE: u32 = 16384;

impl Film {
    /// A film of one pixel.
    pub(crate) const ONE: Film = Film { width: 1, height: 1 };

    /// A film of `width` x `height` pixels.
    pub fn new(width: u32, height: u32) -> Result<Self, SceneError> {
        let ok = |v: u32| (1..=MAX_FILM_SIDE).contains(&v);
        if !ok(width) || !ok(height) {
            return Err(SceneError::OutOfRange(Field::FilmSize));
        }
        // Both fit in u16 after the check above (16384 < 65536).
        Ok(Self { width: width as u16, height: height as u16 })
    }

    /// Width in pixels.
    #[inline]
    pub fn width(&self) -> u32 {
        u32::from(self.width)
    }

    /// Height in pixels.
    #[inline]
    pub fn height(&self) -> u32 {
        u32::from(self.height)
    }

    /// Number of pixels.
    #[inline]
    pub fn pixels(&self) -> u32 {
        self.width() * self.height()
    }
}

/// How the camera is placed, as in the scene file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraDesc {
    /// Eye position.
    pub origin: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Up hint.
    pub up: Vec3,
    /// Field of view in degrees, in (0, 180).
    pub fov_deg: f32,
    /// Axis of the field of view.
    pub fov_axis: FovAxis,
    /// Near clip distance along the view direction (>= 0).
    pub near_clip: f32,
}

/// A validated pinhole camera for one film size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    desc: CameraDesc,
    origin: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_x: f32,
    tan_y: f32,
    near_clip: f32,
    /// The film's size in pixels.
    size: Vec2,
    /// The unnormalised direction through the film's top-left corner, forward - right tan_x +
    /// up tan_y, and its steps per pixel to the right and down: the primary ray through pixel
    /// position (x, y) points along `corner + x step_x + y step_y`.
    corner: Vec3,
    step_x: Vec3,
    step_y: Vec3,
}

impl Camera {
    /// Validates `desc` and derives the camera for `film`.
    pub fn new(desc: CameraDesc, film: Film) -> Result<Self, SceneError> {
        for (v, field) in [
            (desc.origin, Field::CameraOrigin),
            (desc.target, Field::CameraTarget),
            (desc.up, Field::CameraUp),
        ] {
            if !finite3(v) {
                return Err(SceneError::NonFinite(field));
            }
        }
        if !desc.fov_deg.is_finite() {
            return Err(SceneError::NonFinite(Field::FieldOfView));
        }
        if !(desc.fov_deg > 0.0 && desc.fov_deg < 180.0) {
            return Err(SceneError::OutOfRange(Field::FieldOfView));
        }
        if !desc.near_clip.is_finite() {
            return Err(SceneError::NonFinite(Field::NearClip));
        }
        if desc.near_clip < 0.0 {
            return Err(SceneError::OutOfRange(Field::NearClip));
        }
        let forward =
            try_normalize(desc.target - desc.origin).ok_or(SceneError::ZeroDirection(Field::CameraTarget))?;
        if try_normalize(desc.up).is_none() {
            return Err(SceneError::ZeroDirection(Field::CameraUp));
        }
        let right = try_normalize(forward.cross(desc.up)).ok_or(SceneError::UpParallelToView)?;
        let up = right.cross(forward);
        // tan(fov / 2), with fov / 2 in turns: fov_deg / 720.
        let (sin, cos) = sin_cos_turns(desc.fov_deg / 720.0);
        let t = sin / cos;
        let aspect = film.width() as f32 / film.height() as f32;
        let (tan_x, tan_y) = match desc.fov_axis {
            FovAxis::Y => (t * aspect, t),
            FovAxis::X => (t, t / aspect),
        };
        let size = Vec2::new(film.width() as f32, film.height() as f32);
        Ok(Self {
            desc,
            origin: desc.origin,
            forward,
            right,
            up,
            tan_x,
            tan_y,
            near_clip: desc.near_clip,
            size,
            corner: forward - right * tan_x + up * tan_y,
            step_x: right * (2.0 * tan_x / size.x),
            step_y: up * (-2.0 * tan_y / size.y),
        })
    }

    /// The description this camera was built from.
    #[inline]
    pub fn desc(&self) -> CameraDesc {
        self.desc
    }

    /// `p` in view coordinates: its offsets from the camera's origin along the right, up and
    /// forward axes. A point in front (z > 0) lies on the primary ray through
    /// [`Camera::film_at_slopes`] of (x / z, y / z).
    #[inline]
    pub(crate) fn view_of(&self, p: Vec3) -> Vec3 {
        let q = p - self.origin;
        Vec3::new(q.dot(self.right), q.dot(self.up), q.dot(self.forward))
    }

    /// The film point (u, v) whose primary ray has view slopes `a` = x / z and `b` = y / z:
    /// the inverse of the mapping of [`Camera::ray`].
    #[inline]
    pub(crate) fn film_at_slopes(&self, a: f32, b: f32) -> Vec2 {
        Vec2::new(0.5 * (a / self.tan_x + 1.0), 0.5 * (1.0 - b / self.tan_y))
    }

    /// The primary ray through film point `film` (u right, v down, both in [0, 1]) and the
    /// distance along it of the near clip plane: [`Camera::ray_at_pixel`] of `film` times the
    /// film's size.
    #[inline]
    pub fn ray(&self, film: Vec2) -> (Ray, f32) {
        self.ray_at_pixel(film * self.size)
    }

    /// The primary ray through pixel position `p` (x right, y down, in pixels from the film's
    /// top-left corner: pixel (i, j) covers [i, i + 1] x [j, j + 1]) and the distance along it of
    /// the near clip plane.
    #[inline]
    pub fn ray_at_pixel(&self, p: Vec2) -> (Ray, f32) {
        let d = self.corner + self.step_x * p.x + self.step_y * p.y;
        // d's component along `forward` is one (the steps are across it), so the clip plane,
        // perpendicular to `forward` at `near_clip`, lies at near_clip |d| along the unit ray.
        let len2 = dot(d, d);
        let (dir, t_near) = if positive_finite(len2) {
            let len = sqrt(len2);
            (d * (1.0 / len), self.near_clip * len)
        } else {
            (self.forward, self.near_clip)
        };
        (Ray { origin: self.origin, dir }, t_near)
    }
}

/// The unit tests' camera: on the +z axis, 5 units from the origin, looking at it, `fov_deg`
/// vertically.
impl Image for Film {
    fn put(&self, out: &mut dyn FnMut(u32)) {
        out(self.width());
        out(self.height());
    }
    fn get(words: &mut Words<'_>) -> Option<Self> {
        Film::new(words.u32()?, words.u32()?).ok()
    }
}

impl Camera {
    /// A camera that sees nothing, for a scene that is about to be loaded
    /// ([`Scene::load_image`](crate::Scene::load_image)).
    pub(crate) const EMPTY: Camera = {
        let zero = Vec3::ZERO;
        let desc = CameraDesc {
            origin: zero,
            target: zero,
            up: zero,
            fov_deg: 0.0,
            fov_axis: FovAxis::Y,
            near_clip: 0.0,
        };
        Camera {
            desc,
            origin: zero,
            forward: zero,
            right: zero,
            up: zero,
            tan_x: 0.0,
            tan_y: 0.0,
            near_clip: 0.0,
            size: Vec2::ZERO,
            corner: zero,
            step_x: zero,
            step_y: zero,
        }
    };
}

impl Image for Camera {
    fn put(&self, out: &mut dyn FnMut(u32)) {
        let d = &self.desc;
        for v in [
            d.origin,
            d.target,
            d.up,
            self.origin,
            self.forward,
            self.right,
            self.up,
            self.corner,
            self.step_x,
            self.step_y,
        ] {
            v.put(out);
        }
        for v in [d.fov_deg, d.near_clip, self.tan_x, self.tan_y, self.near_clip] {
            v.put(out);
        }
        out(match d.fov_axis {
            FovAxis::X => 0,
            FovAxis::Y => 1,
        });
        self.size.put(out);
    }
    fn get(w: &mut Words<'_>) -> Option<Self> {
        let a: [u32; 38] = w.take()?;
        let fov_axis = match a[35] {
            0 => FovAxis::X,
            1 => FovAxis::Y,
            _ => return None,
        };
        let desc = CameraDesc {
            origin: vec3(&a, 0),
            target: vec3(&a, 3),
            up: vec3(&a, 6),
            fov_deg: float(&a, 30),
            fov_axis,
            near_clip: float(&a, 31),
        };
        Some(Camera {
            desc,
            origin: vec3(&a, 9),
            forward: vec3(&a, 12),
            right: vec3(&a, 15),
            up: vec3(&a, 18),
            corner: vec3(&a, 21),
            step_x: vec3(&a, 24),
            step_y: vec3(&a, 27),
            tan_x: float(&a, 32),
            tan_y: float(&a, 33),
            near_clip: float(&a, 34),
            size: Vec2::new(float(&a, 36), float(&a, 37)),
        })
    }
}

#[cfg(test)]
pub(crate) fn test_desc(fov_deg: f32) -> CameraDesc {
    CameraDesc {
        origin: Vec3::new(0.0, 0.0, 5.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_deg,
        fov_axis: FovAxis::Y,
        near_clip: 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn desc() -> CameraDesc {
        test_desc(90.0)
    }

    #[test]
    fn film_corners_follow_the_format() {
        let cam = Camera::new(desc(), Film::new(200, 100).unwrap()).unwrap();
        let (center, _) = cam.ray(Vec2::splat(0.5));
        assert!((center.dir - -Vec3::Z).length() < 1e-6);
        // Top-left corner: u = 0 left, v = 0 top; tan_y = 1, tan_x = 2.
        let (tl, _) = cam.ray(Vec2::ZERO);
        let expect = Vec3::new(-2.0, 1.0, -1.0).normalize();
        assert!((tl.dir - expect).length() < 1e-6, "{}", tl.dir);
    }

    #[test]
    fn rejects_bad_cameras() {
        let film = Film::new(4, 4).unwrap();
        let mut d = desc();
        d.up = -Vec3::Z;
        assert_eq!(Camera::new(d, film), Err(SceneError::UpParallelToView));
        let mut d = desc();
        d.fov_deg = 180.0;
        assert_eq!(Camera::new(d, film), Err(SceneError::OutOfRange(Field::FieldOfView)));
        let mut d = desc();
        d.target = d.origin;
        assert_eq!(Camera::new(d, film), Err(SceneError::ZeroDirection(Field::CameraTarget)));
        assert_eq!(Film::new(0, 4), Err(SceneError::OutOfRange(Field::FilmSize)));
        assert_eq!(Film::new(16385, 4), Err(SceneError::OutOfRange(Field::FilmSize)));
    }
}
