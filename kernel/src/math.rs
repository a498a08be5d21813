//! The one place that chooses the math backend: glam vectors (scalar `Vec3`, no SIMD) and libm
//! functions, so the host and a microcontroller run the same f32 operations bit for bit.

pub use glam::{Vec2, Vec3};

/// Linear RGB radiance, irradiance or reflectance, one f32 per channel.
pub type Rgb = Vec3;

/// pi in f32.
pub const PI: f32 = core::f32::consts::PI;
/// 1 / pi in f32.
pub const INV_PI: f32 = core::f32::consts::FRAC_1_PI;

/// Square root of a value clamped at zero (rounding can make a true zero slightly negative).
#[inline]
pub fn safe_sqrt(x: f32) -> f32 {
    libm::sqrtf(x.max(0.0))
}

/// Sine and cosine of an angle in radians.
#[inline]
pub fn sin_cos(x: f32) -> (f32, f32) {
    libm::sincosf(x)
}

/// Arc cosine with its argument clamped to [-1, 1].
#[inline]
pub fn safe_acos(x: f32) -> f32 {
    libm::acosf(x.clamp(-1.0, 1.0))
}

/// Tangent.
#[inline]
pub fn tan(x: f32) -> f32 {
    libm::tanf(x)
}

/// `x` raised to `y`.
#[inline]
pub fn powf(x: f32, y: f32) -> f32 {
    libm::powf(x, y)
}

/// Rec. 709 luminance of a linear RGB value.
#[inline]
pub fn luminance(c: Rgb) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// True when every component of the vector is finite.
#[inline]
pub fn finite3(v: Vec3) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

/// An orthonormal frame around a unit normal: local `z` is the normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// First tangent.
    pub t: Vec3,
    /// Second tangent.
    pub b: Vec3,
    /// Normal.
    pub n: Vec3,
}

impl Frame {
    /// Builds a frame around the unit vector `n` (Duff et al. 2017, branchless, no singularity).
    #[inline]
    pub fn from_normal(n: Vec3) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        Self {
            t: Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
            b: Vec3::new(b, sign + n.y * n.y * a, -n.y),
            n,
        }
    }

    /// World direction to local coordinates.
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.t), v.dot(self.b), v.dot(self.n))
    }

    /// Local direction to world coordinates.
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.t * v.x + self.b * v.y + self.n * v.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_is_orthonormal_for_any_normal() {
        for n in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(0.3, -0.4, -0.866).normalize(),
            Vec3::new(1e-7, 0.0, -1.0).normalize(),
        ] {
            let f = Frame::from_normal(n);
            assert!((f.t.length() - 1.0).abs() < 1e-5, "{n}");
            assert!((f.b.length() - 1.0).abs() < 1e-5, "{n}");
            assert!(f.t.dot(f.b).abs() < 1e-5 && f.t.dot(n).abs() < 1e-5 && f.b.dot(n).abs() < 1e-5);
            let v = Vec3::new(0.2, -0.5, 0.7);
            assert!((f.to_local(f.to_world(v)) - v).length() < 1e-5);
        }
    }
}
