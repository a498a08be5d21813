//! What light sampling takes and gives: the shading point, the light chosen, and the sample
//! drawn on it.

use crate::num::{Rgb, Vec3};
use crate::scene::{LightId, Material, ShapeId};

/// The point light is sampled for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingPoint {
    /// Position.
    pub p: Vec3,
    /// Unit geometric normal of the front side.
    pub n: Vec3,
    /// Unit direction towards the viewer (world).
    pub wo: Vec3,
    /// The receiver's BSDF (selection by contribution and lobe mixing follow it).
    pub bsdf: Material,
}

/// A light chosen for a light sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightChoice {
    /// The light.
    pub light: LightId,
    /// The probability with which it was chosen, P(light).
    pub probability: f32,
}

/// A sample drawn on a chosen light, seen from the shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the shading point to the light (world).
    pub wi: Vec3,
    /// Distance to the sampled point.
    pub distance: f32,
    /// Incident radiance (for a point light: intensity / distance^2).
    pub radiance: Rgb,
    /// Pdf per unit solid angle of `wi` given the light, p_w(wi | light); 1 for a delta light.
    /// Never includes the light's selection probability.
    pub pdf: f32,
    /// True for a delta light: it has no pdf in solid angle and always gets weight one.
    pub delta: bool,
    /// The shape the point lies on (area lights): the shadow ray may end on it.
    pub emitter: Option<ShapeId>,
}

impl LightSample {
    /// A sample of an area light towards `wi` at `distance` with `pdf`; the caller fills in its
    /// radiance and emitter.
    #[inline]
    pub(crate) fn towards(wi: Vec3, distance: f32, pdf: f32) -> Self {
        LightSample { wi, distance, radiance: Rgb::ZERO, pdf, delta: false, emitter: None }
    }
}
