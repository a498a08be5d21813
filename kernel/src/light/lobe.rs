//! Light samples that follow a glossy receiver's lobe where it meets a light
//! ([`LobeMixing::On`]).
//!
//! Where a near-mirror reflects an area light, the integrand f L cos over the light's directions
//! is a narrow GGX lobe cut by the light's outline: at the rim of the reflection and in the glow
//! around it, the light technique's samples (uniform over the light) almost all fall where f is
//! negligible, and the BSDF technique's samples (the whole lobe) mostly miss the light. MIS
//! picks the better of two bad estimates there. This module adds a third way into the light
//! technique: directions from the receiver's lobe restricted to the box of microfacet slopes that
//! reflect towards the light ([`SlopeBox`]), so the samples follow f *and* land on the light. The
//! light technique becomes a mixture, p_l = P(light) ((1 - s) p_light + s p_lobe), sampled with
//! the same single random pair (its first number picks the part and is rescaled), and is still
//! one technique to the MIS weights: its pdf is evaluated for any direction, so both
//! techniques' weights of a direction still sum to one.
//!
//! It applies to GGX receivers whose lobe is narrower than the light's angular size
//! ([`LOBE_NARROWER`]); elsewhere light sampling is unchanged, bit for bit.
//!
//! A build that does not name [`On`] contains none of it.

use crate::geometry::Shape;
use crate::light::quad::QuadSampler;
use crate::light::sample::ShadingPoint;
use crate::light::sphere::SphereSampler;
use crate::num::{Frame, Vec2, Vec3, dot, sqrt};
use crate::sampling::{
    SlopeBox, cone_one_minus_cos, ggx_reflection_in_pdf, nearest_edge, sample_ggx_reflection_in,
};
use crate::scene::Material;

crate::choices! {
    /// Whether light samples also follow a glossy receiver's lobe where it meets the light.
    pub enum LobeMixing: "lobe mixing" {
        /// Light samples from the light alone ([`Off`]).
        Off = "off", "light samples from the light alone";
        /// A share of the light samples ([`LOBE_SHARE`]) from the receiver's lobe towards the
        /// light, at GGX receivers whose lobe is narrower than the light ([`LOBE_NARROWER`]) ([`On`]).
        On = "on", "light samples also from a glossy receiver's lobe where it is narrower than the light";
    }
}

/// Whether a glossy receiver's lobe joins the light samples: a strategy type per setting.
pub trait LobeSampler: Sync + 'static {
    /// Its name among the settings.
    const KIND: LobeMixing;

    /// The lobe of the receiver at `at` towards the area light of shape `shape`, where it joins
    /// the light samples; only for the kinds of lights the scene may have (see
    /// [`SphereSampler::PRESENT`] and [`QuadSampler::PRESENT`] of its strategies `Sp` and `Q`).
    fn towards<Sp: SphereSampler, Q: QuadSampler>(shape: &Shape, at: &ShadingPoint) -> Option<Lobe>;
}

/// Light samples from the light alone.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Off;

impl LobeSampler for Off {
    const KIND: LobeMixing = LobeMixing::Off;

    #[inline(always)]
    fn towards<Sp: SphereSampler, Q: QuadSampler>(_: &Shape, _: &ShadingPoint) -> Option<Lobe> {
        None
    }
}

/// Light samples also from a glossy receiver's lobe where it applies ([`Lobe::towards`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct On;

impl LobeSampler for On {
    const KIND: LobeMixing = LobeMixing::On;

    #[inline]
    fn towards<Sp: SphereSampler, Q: QuadSampler>(shape: &Shape, at: &ShadingPoint) -> Option<Lobe> {
        Lobe::towards::<Sp, Q>(shape, at.p, at.n, at.wo, &at.bsdf)
    }
}

/// The lobe's part applies where the GGX alpha is below this fraction of the sine of the light's
/// angular radius: a lobe narrower than the light has a rim and a glow that neither the light's
/// nor the BSDF's samples find; where the lobe is wider, the light's own samples are good.
/// (Chosen by relative MSE at equal spp, `bench/examples/lobe_constants.rs`, run committed in
/// docs/techniques/lobe-constants.md: on Veach 1.95e-4 at 1/2, 2.08e-4 at 1/4, 2.26e-4 at 1,
/// 3.98e-4 at every GGX receiver, 4.72e-4 without the lobe.)
pub const LOBE_NARROWER: f32 = 0.5;

/// The lobe does not apply where its box of slopes holds every slope within this many alphas of
/// the mirror direction: the lobe lies inside the light, and BSDF sampling finds it.
pub const LOBE_INSIDE: f32 = 10.0;

/// The lobe does not apply where the mirror direction lies farther than this many alphas (an
/// angle) outside a quad light: its slopes are then at least half as many alphas from the
/// quad's (a half vector turns half as far as the reflected direction, and a slope at least as
/// far as its normal), where the lobe's tail holds under 1e-4 of it.
pub const LOBE_REACH: f32 = 100.0;

/// The lobe's share of the light samples where it applies. (As above, with the bound at 1/2:
/// geometric mean over Veach, stress, mirror_lights and glossy_lights, relative to 3/4: 1.095 at
/// 1/2, 1.49 at 1/4; 0.959 at 7/8, better on stress and mirror_lights but worse on Veach, a
/// margin too small to give up more of the light's own samples for.)
pub const LOBE_SHARE: f32 = 0.75;

/// How far outside a light's bounding sphere a receiver must be for its lobe to apply: d^2 > r^2
/// times this.
const CLEAR: f32 = 1.001;

/// A GGX receiver's lobe towards one light: the receiver's frame, `wo` in it, and the box of
/// slopes that reflect towards the light.
#[derive(Clone, Copy, Debug)]
pub struct Lobe {
    frame: Frame,
    wo: Vec3,
    slopes: SlopeBox,
}

impl Lobe {
    /// The lobe of the receiver at `x` (unit normal `n`, material `bsdf`, world `wo`) towards the
    /// area light of shape `shape`, where the mixture applies: a GGX receiver whose lobe is
    /// narrower than the light ([`LOBE_NARROWER`]), outside the light's bounding sphere, and a
    /// box of slopes that faces it. The box is exact to first order at a sphere's rim
    /// ([`SlopeBox::facing_cone`]) and at the edge of a quad nearest the mirror direction
    /// ([`SlopeBox::facing_edge`]), within [`LOBE_REACH`] alphas outside it and twice
    /// [`LOBE_INSIDE`] inside.
    /// (Out of line: a firmware that carries it shows it by name.)
    #[inline(never)]
    pub fn towards<Sp: SphereSampler, Q: QuadSampler>(
        shape: &Shape,
        x: Vec3,
        n: Vec3,
        wo: Vec3,
        bsdf: &Material,
    ) -> Option<Self> {
        let Material::GgxConductor { alpha, .. } = *bsdf else { return None };
        // Only for the kinds of lights the scene may have.
        match shape.as_sphere() {
            Some(_) if !Sp::PRESENT => return None,
            None if !Q::PRESENT => return None,
            _ => {}
        }
        let (center, radius) = match shape.as_sphere() {
            Some(sphere) => sphere,
            None => (shape.centroid(), shape.bounding_radius()),
        };
        let to_c = center - x;
        let d2 = dot(to_c, to_c);
        let r2 = radius * radius;
        let sin_max = sqrt(r2 / d2);
        // Clear of the light (not on a sphere light itself, where rounding puts `x` either side).
        if !(d2 > r2 * CLEAR && alpha < LOBE_NARROWER * sin_max) {
            return None;
        }
        let frame = Frame::from_normal(n);
        let wo = frame.to_local(wo);
        let slopes = match (shape.as_sphere(), shape.corners()) {
            (Some(_), _) => {
                let axis = frame.to_local(to_c / sqrt(d2));
                SlopeBox::facing_cone(wo, alpha, axis, 1.0 - cone_one_minus_cos(r2 / d2), sin_max)
            }
            (None, Some(c)) => {
                // Where the mirror direction lies against the quad's outline decides first: far
                // outside or deep inside, nothing more is needed.
                let corners = c.map(|p| frame.to_local(p - x));
                let edge = nearest_edge(Vec3::new(-wo.x, -wo.y, wo.z), &corners)?;
                if !(edge.sine > -LOBE_REACH * alpha && edge.sine < 2.0 * LOBE_INSIDE * alpha) {
                    return None;
                }
                let mid = |a: Vec3, b: Vec3| (a + b) * 0.5;
                let [c0, c1, c2, c3] = corners;
                let points = [c0, mid(c0, c1), c1, mid(c1, c2), c2, mid(c2, c3), c3, mid(c3, c0)];
                let outline = points.map(|p| p / sqrt(dot(p, p)));
                SlopeBox::facing_edge(wo, alpha, &edge, &outline)
            }
            (None, None) => None,
        }?;
        // A lobe well inside the light: BSDF sampling alone finds it (its samples reach the
        // light but for the lobe's tail beyond LOBE_INSIDE alpha, ~1 %), and a mixture would
        // only add the light part's variance to it.
        if slopes.holds_disc(LOBE_INSIDE * alpha) {
            return None;
        }
        Some(Lobe { frame, wo, slopes })
    }

    /// A world direction from the lobe towards the light (`None` when it leaves the upper
    /// hemisphere; it may still miss the light).
    #[inline]
    pub fn sample(&self, u: Vec2) -> Option<Vec3> {
        sample_ggx_reflection_in(self.wo, &self.slopes, u).map(|wi| self.frame.to_world(wi))
    }

    /// Pdf per unit solid angle of [`Lobe::sample`] drawing the world direction `wi`.
    #[inline]
    pub fn pdf(&self, wi: Vec3) -> f32 {
        ggx_reflection_in_pdf(self.wo, &self.slopes, self.frame.to_local(wi))
    }
}
