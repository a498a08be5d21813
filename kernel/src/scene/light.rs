//! Lights, the values: area emitters on shapes (constant radiance, front side only) and point
//! lights, with their emission validated once ([`Emission`]). How a light is chosen and how a
//! point on it is drawn is the light sampler's job ([`crate::light`]).

use crate::error::{Field, SceneError};
use crate::geometry::Shape;
use crate::num::{PI, Rgb, Vec3, channel_mean, finite3, max0};
use crate::scene::ids::ShapeId;
use crate::words::{Image, Words, vec3};

/// The largest radiance (area lights) or intensity (point lights) a scene accepts, per channel:
/// with [`MAX_CONTRIBUTION`](crate::integrator::MAX_CONTRIBUTION) it keeps every pixel's running
/// sums finite (see there). Larger values are `SceneError::OutOfRange`.
pub const MAX_EMISSION: f32 = 1e20;

/// Emitted radiance (area lights) or radiant intensity (point lights): finite, non-negative and at
/// most [`MAX_EMISSION`] in every channel. The one place these values are checked; the scene and
/// the scene format ask it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emission(Rgb);

impl Emission {
    /// An area light's radiance.
    pub fn radiance(c: Rgb) -> Result<Self, SceneError> {
        Self::checked(c, Field::Radiance)
    }

    /// A point light's intensity (W/sr per channel).
    pub fn intensity(c: Rgb) -> Result<Self, SceneError> {
        Self::checked(c, Field::Intensity)
    }

    fn checked(c: Rgb, field: Field) -> Result<Self, SceneError> {
        if !finite3(c) {
            return Err(SceneError::NonFinite(field));
        }
        if c.min_element() < 0.0 || c.max_element() > MAX_EMISSION {
            return Err(SceneError::OutOfRange(field));
        }
        Ok(Self(c))
    }

    /// The value.
    #[inline]
    pub fn rgb(self) -> Rgb {
        self.0
    }
}

/// The closed set of lights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Constant radiance on the front side of a scene shape.
    Area {
        /// The emitting shape.
        shape: ShapeId,
        /// Emitted radiance.
        radiance: Rgb,
    },
    /// A point light (a delta light: only light sampling can find it).
    Point {
        /// Position.
        position: Vec3,
        /// Radiant intensity (W/sr per channel).
        intensity: Rgb,
    },
}

impl Light {
    /// An area light of `radiance` on `shape`.
    pub fn area(shape: ShapeId, radiance: Rgb) -> Result<Self, SceneError> {
        Ok(Light::Area { shape, radiance: Emission::radiance(radiance)?.rgb() })
    }

    /// A point light of `intensity` at `position` (finite).
    pub fn point(position: Vec3, intensity: Rgb) -> Result<Self, SceneError> {
        if !finite3(position) {
            return Err(SceneError::NonFinite(Field::Position));
        }
        Ok(Light::Point { position, intensity: Emission::intensity(intensity)?.rgb() })
    }

    /// The emitting shape of an area light.
    #[inline]
    pub fn shape(&self) -> Option<ShapeId> {
        match *self {
            Light::Area { shape, .. } => Some(shape),
            Light::Point { .. } => None,
        }
    }

    /// Emitted power (mean of the channels, [`channel_mean`]), the weight of light selection by power. `shape` is the emitting
    /// shape of an area light (ignored for point lights).
    pub fn power(&self, shape: Option<&Shape>) -> f32 {
        match *self {
            Light::Area { radiance, .. } => {
                shape.map_or(0.0, |s| PI * max0(channel_mean(radiance)) * s.area())
            }
            Light::Point { intensity, .. } => 4.0 * PI * max0(channel_mean(intensity)),
        }
    }
}
impl Image for Light {
    fn put(&self, out: &mut dyn FnMut(u32)) {
        match *self {
            Light::Area { shape, radiance } => {
                out(0);
                out(u32::from(shape.raw()));
                radiance.put(out);
            }
            Light::Point { position, intensity } => {
                out(1);
                position.put(out);
                intensity.put(out);
            }
        }
    }
    fn get(w: &mut Words<'_>) -> Option<Self> {
        Some(match w.u32()? {
            0 => {
                let a: [u32; 4] = w.take()?;
                Light::Area { shape: ShapeId::new(u16::try_from(a[0]).ok()?), radiance: vec3(&a, 1) }
            }
            1 => {
                let a: [u32; 6] = w.take()?;
                Light::Point { position: vec3(&a, 0), intensity: vec3(&a, 3) }
            }
            _ => return None,
        })
    }
}
