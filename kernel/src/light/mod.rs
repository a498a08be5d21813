//! The light sampler: light sampling's one home. It chooses a light for a light sample
//! ([`LightSelection`]: uniformly, by power, or by estimated contribution at the shading point)
//! and draws a direction to a point on it (sphere lights by area or in the cone they subtend,
//! [`SphereSampling`]), and it evaluates the probabilities of what it drew, as pairs:
//!
//! - [`LightSampler::select`] / [`LightSampler::pmf`]: the light and its selection probability
//!   P(light) at a shading point, both read from the point's [`SelectionAt`]
//!   ([`LightSampler::selection_at`], computed once per shading point), so they cannot disagree;
//! - [`LightSampler::sample`] / [`LightSampler::pdf`]: the light sample and its pdf per unit solid
//!   angle at `x`, p_w(wi | light), selection not included ([`LightSample::pdf`]).
//!
//! The light technique's pdf is their product, p_l = P(light) p_w, and the estimator writes it so.

pub mod importance;
pub mod lobe;

use crate::geometry::Rectangle;
use crate::geometry::{Ray, Shape, SurfacePoint};
use crate::light::importance::{Receiver, weighs_bsdf};
use crate::light::lobe::{LOBE_SHARE, Lobe, LobeMixing};
use crate::num::{Frame, Rgb, Vec2, Vec3, dot, from_local_around, max0, positive_finite, safe_sqrt, sqrt};
use crate::sampling::{
    GRID, GridDistribution, SphericalRectangle, bilinear_pdf, cone_one_minus_cos,
    invert_spherical_rectangle_sample, sample_bilinear, sample_spherical_rectangle, sample_uniform_cone,
    spherical_rectangle, spherical_rectangle_cosines, spherical_rectangle_pdf, uniform_cone_pdf,
};
use crate::scene::Light;
use crate::scene::Material;
use crate::scene::Scene;
use crate::scene::{LightId, ShapeId};

/// How points on sphere lights are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SphereSampling {
    /// Uniformly by area, converted to solid angle (the lecture's formulation); about half the
    /// points lie on the far side and contribute nothing.
    Area,
    /// Uniformly inside the cone the sphere subtends (falls back to area from inside).
    Cone,
}

impl SphereSampling {
    /// The default strategy (a constant, for the settings' `const` constructors).
    pub const DEFAULT: Self = SphereSampling::Cone;

    /// Every strategy: the lecture's, then the default.
    pub const ALL: [SphereSampling; 2] = [SphereSampling::Area, SphereSampling::Cone];

    /// The strategy's name (command line, reports).
    pub fn name(self) -> &'static str {
        match self {
            SphereSampling::Area => "area",
            SphereSampling::Cone => "cone",
        }
    }

    /// One line about the strategy (command-line help).
    pub fn summary(self) -> &'static str {
        match self {
            SphereSampling::Area => "uniformly by area (the lecture's formulation)",
            SphereSampling::Cone => "uniformly in the cone the sphere subtends",
        }
    }

    /// The strategy called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }
}

impl core::fmt::Display for SphereSampling {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

impl Default for SphereSampling {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// How points on quad lights are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum QuadSampling {
    /// Uniformly by area, converted to solid angle.
    Area,
    /// Uniformly in the solid angle the quad subtends (spherical rectangles, Ureña et al. 2013);
    /// by area for quads that are not rectangles and where f32 cannot resolve the solid angle
    /// (tiny or grazing rectangles, see [`spherical_rectangle`]).
    SolidAngle,
    /// In solid angle, with the 2-D sample first warped towards the receiver's cosine (Hart et
    /// al. 2020, as pbrt-v4 does for rectangles): a bilinear density whose corner values are the
    /// cosines towards the rectangle's corners ([`spherical_rectangle_cosines`]); the pdf is the
    /// spherical rectangle's times the bilinear one. The same fallback to area as
    /// [`QuadSampling::SolidAngle`].
    SolidAngleCosine,
}

impl Default for QuadSampling {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl QuadSampling {
    /// The default strategy (a constant, for the settings' `const` constructors).
    pub const DEFAULT: Self = QuadSampling::Area;

    /// Every strategy, the default first.
    pub const ALL: [QuadSampling; 3] =
        [QuadSampling::Area, QuadSampling::SolidAngle, QuadSampling::SolidAngleCosine];

    /// The strategy's name (command line, reports).
    pub fn name(self) -> &'static str {
        match self {
            QuadSampling::Area => "area",
            QuadSampling::SolidAngle => "solid-angle",
            QuadSampling::SolidAngleCosine => "solid-angle-cosine",
        }
    }

    /// One line about the strategy (command-line help).
    pub fn summary(self) -> &'static str {
        match self {
            QuadSampling::Area => "uniformly by area",
            QuadSampling::SolidAngle => {
                "uniformly in solid angle (spherical rectangles; by area where unstable)"
            }
            QuadSampling::SolidAngleCosine => {
                "in solid angle, warped by the receiver's cosine (Hart et al. 2020)"
            }
        }
    }

    /// The strategy called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|q| q.name() == name)
    }
}

impl core::fmt::Display for QuadSampling {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// How a light is chosen when a scene has several.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LightSelection {
    /// Every light equally likely.
    Uniform,
    /// Proportional to emitted power (the mean of its channels), on the grid of the random
    /// number (see [`GridDistribution`]): every light that emits is chosen with exactly the
    /// probability the weights are given.
    Power,
    /// Proportional to each light's estimated contribution at the shading point, BSDF included
    /// ([`LightCone::contribution`](crate::light::importance::LightCone::contribution)), mixed
    /// with a share [`CONTRIBUTION_FLOOR`] of its BSDF-free importance
    /// ([`LightCone::importance`](crate::light::importance::LightCone::importance)) so that every
    /// light that can contribute keeps a non-zero probability (on Lambertian receivers, by the
    /// importance alone); on the grid of the random number like power. A scene's only light is
    /// chosen with probability one; a light that certainly sends nothing to the point is never
    /// chosen. Costs O(lights) per shading point.
    Contribution,
}

impl LightSelection {
    /// The default selection (a constant, for the settings' `const` constructors).
    pub const DEFAULT: Self = LightSelection::Uniform;
}

impl Default for LightSelection {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The share of the BSDF-free importance in light selection by contribution: every light that
/// can send light to the shading point is chosen with at least this share of its importance's
/// probability, even where the BSDF toward its centre is zero (a near-mirror GGX lobe that
/// misses the centre of a light whose edge it sees).
pub const CONTRIBUTION_FLOOR: f32 = 0.1;

impl LightSelection {
    /// Every strategy, the default first.
    pub const ALL: [LightSelection; 3] =
        [LightSelection::Uniform, LightSelection::Power, LightSelection::Contribution];

    /// The strategy's name (command line, the page, charts).
    pub fn name(self) -> &'static str {
        match self {
            LightSelection::Uniform => "uniform",
            LightSelection::Power => "power",
            LightSelection::Contribution => "contribution",
        }
    }

    /// One line about the strategy (command-line help).
    pub fn summary(self) -> &'static str {
        match self {
            LightSelection::Uniform => "every light equally likely",
            LightSelection::Power => "proportional to emitted power",
            LightSelection::Contribution => "proportional to the estimated contribution at the shading point",
        }
    }

    /// The strategy called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }
}

/// The point light is sampled for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingPoint {
    /// Position.
    pub p: Vec3,
    /// Unit geometric normal of the front side.
    pub n: Vec3,
    /// Unit direction towards the viewer (world).
    pub wo: Vec3,
    /// The receiver's BSDF (selection by contribution weighs lights by it).
    pub bsdf: Material,
}

/// Light selection at one shading point: what [`LightSampler::select`] draws from and
/// [`LightSampler::pmf`] reads, computed once by [`LightSampler::selection_at`].
#[derive(Clone, Debug, PartialEq)]
pub struct SelectionAt<const L: usize> {
    /// The lights' probabilities here (selection by contribution); empty for the strategies
    /// that do not depend on the point, and where no light can contribute.
    local: GridDistribution<L>,
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
    fn towards(wi: Vec3, distance: f32, pdf: f32) -> Self {
        LightSample { wi, distance, radiance: Rgb::ZERO, pdf, delta: false, emitter: None }
    }
}

/// Light sampling in one scene with one strategy for each choice.
#[derive(Clone, Copy, Debug)]
pub struct LightSampler<'a, const S: usize, const L: usize, const M: usize> {
    scene: &'a Scene<S, L, M>,
    selection: LightSelection,
    spheres: SphereSampling,
    quads: QuadSampling,
    lobe: LobeMixing,
}

impl<'a, const S: usize, const L: usize, const M: usize> LightSampler<'a, S, L, M> {
    /// The sampler of `scene`'s lights choosing by `selection`, drawing on spheres by `spheres`
    /// (and on quads by area, see [`LightSampler::with_quad_sampling`]).
    #[inline]
    pub fn new(scene: &'a Scene<S, L, M>, selection: LightSelection, spheres: SphereSampling) -> Self {
        Self { scene, selection, spheres, quads: QuadSampling::Area, lobe: LobeMixing::Off }
    }

    /// The same sampler drawing on quads by `quads`.
    #[inline]
    pub fn with_quad_sampling(mut self, quads: QuadSampling) -> Self {
        self.quads = quads;
        self
    }

    /// The same sampler with light samples also following a glossy receiver's lobe
    /// ([`LobeMixing`]; in a build without the `lobe` feature, as off).
    #[inline]
    pub fn with_lobe_mixing(mut self, lobe: LobeMixing) -> Self {
        self.lobe = lobe;
        self
    }

    /// Light selection at `at`: for selection by contribution, each light's estimated
    /// contribution there mixed with its importance (O(lights)); nothing for the others.
    #[inline]
    pub fn selection_at(&self, at: &ShadingPoint) -> SelectionAt<L> {
        if !self.selects_locally() {
            return SelectionAt { local: GridDistribution::default() };
        }
        let frame = Frame::from_normal(at.n);
        self.selection_in(at, &frame, frame.to_local(at.wo))
    }

    /// [`LightSampler::selection_at`] given the receiver's frame (from its normal,
    /// [`Frame::from_normal`]) and `at.wo` in it, `wo`, which the caller has already computed.
    #[inline]
    pub fn selection_in(&self, at: &ShadingPoint, frame: &Frame, wo: Vec3) -> SelectionAt<L> {
        if !self.selects_locally() {
            return SelectionAt { local: GridDistribution::default() };
        }
        self.by_contribution(at, frame, wo)
    }

    /// The selection by contribution of [`LightSampler::selection_in`]. Out of line: the other
    /// strategies' code around it stays small.
    #[inline(never)]
    fn by_contribution(&self, at: &ShadingPoint, frame: &Frame, wo: Vec3) -> SelectionAt<L> {
        let lights = self.scene.light_geometry();
        let n = lights.geometry().len().min(L);
        // The BSDF's part, if it has one: in the receiver's frame.
        let receiver = weighs_bsdf(&at.bsdf).then(|| Receiver::new(&at.bsdf.seen_from(wo), frame));
        let (mut importance, mut contribution) = ([0.0f32; L], [0.0f32; L]);
        lights.weights(at.p, at.n, receiver.as_ref(), |k, i, c| {
            if let (Some(slot), Some(slot_c)) = (importance.get_mut(k), contribution.get_mut(k)) {
                *slot = i;
                *slot_c = c;
            }
        });
        let importance = &mut importance[..n];
        if receiver.is_some() {
            // The mixture (1 - floor) c_k / sum c + floor i_k / sum i, each part where it has a sum.
            let sum = |w: &[f32]| w.iter().sum::<f32>();
            let (total_i, total_c) = (sum(importance), sum(&contribution[..n]));
            let (scale_i, scale_c) = match (total_i > 0.0, total_c > 0.0) {
                (true, true) => (CONTRIBUTION_FLOOR / total_i, (1.0 - CONTRIBUTION_FLOOR) / total_c),
                (false, true) => (0.0, 1.0),
                (_, false) => (1.0, 0.0),
            };
            for (i, c) in importance.iter_mut().zip(&contribution) {
                *i = *i * scale_i + *c * scale_c;
            }
        }
        SelectionAt { local: GridDistribution::new(importance) }
    }

    /// True when the selection depends on the shading point: by contribution, among several
    /// lights (a single light is chosen with probability one, like uniform selection does).
    #[inline]
    pub(crate) fn selects_locally(&self) -> bool {
        self.selection == LightSelection::Contribution && self.scene.lights().len() > 1
    }

    /// Chooses a light at the shading point of `at` with the random number `u` in [0, 1) (on
    /// the 2^24 grid of [`Sampler::next_f32`](crate::sampling::sampler::Sampler::next_f32)); `None` when the
    /// scene has no light (or, selecting by contribution, no light can contribute there).
    #[inline]
    pub fn select(&self, at: &SelectionAt<L>, u: f32) -> Option<LightChoice> {
        let k = ((u * GRID as f32) as u32).min(GRID - 1);
        self.select_reusing(at, k << 8).map(|(chosen, _)| chosen)
    }

    /// Chooses a light like [`LightSampler::select`] with the top 24 of the 32 random `bits`,
    /// and returns with it the bits rescaled within the chosen light's share of the numbers
    /// ([`DiscreteSample::reused`](crate::sampling::DiscreteSample::reused)): uniform in [0, 1) and independent of the choice, the first
    /// coordinate of the point on the light, so that selection and position stay one
    /// stratified 2-D sample ([`Sampler::next_2d_reusable`](crate::sampling::sampler::Sampler::next_2d_reusable)).
    #[inline]
    pub fn select_reusing(&self, at: &SelectionAt<L>, bits: u32) -> Option<(LightChoice, f32)> {
        let powers = self.scene.light_powers();
        let drawn = if self.selects_locally() {
            at.local.sample_reusing(bits)
        } else if self.selection == LightSelection::Power && !powers.is_empty() {
            powers.sample_reusing(bits)
        } else {
            // Uniform (also when no light has power).
            self.scene.light_uniform().sample_reusing(bits)
        }?;
        let chosen = LightChoice { light: LightId::new(drawn.index as u16), probability: drawn.probability };
        Some((chosen, drawn.reused))
    }

    /// The probability with which [`LightSampler::select`] chooses `light` at the shading point
    /// of `at`.
    #[inline]
    pub fn pmf(&self, at: &SelectionAt<L>, light: LightId) -> f32 {
        let n = self.scene.lights().len();
        if light.index() >= n {
            return 0.0;
        }
        if self.selects_locally() {
            return at.local.pmf(light.index());
        }
        let powers = self.scene.light_powers();
        match self.selection {
            LightSelection::Power if !powers.is_empty() => powers.pmf(light.index()),
            _ => self.scene.light_uniform().pmf(light.index()),
        }
    }

    /// Draws a point on `light` as seen from the shading point `at` with the random numbers `u`;
    /// `None` when the sample carries no light (see [`Light::sample_li`]) or the scene has no
    /// such light. With [`LobeMixing::On`], where the receiver's lobe applies, a share of the
    /// samples ([`LOBE_SHARE`], by `u.x`, rescaled) comes from the lobe instead, and the pdf is
    /// the mixture's.
    #[inline]
    pub fn sample(&self, light: LightId, at: &ShadingPoint, u: Vec2) -> Option<LightSample> {
        let Some((lobe, shape, radiance, emitter)) = self.lobe_towards(light, at) else {
            return self.sample_light(light, at, u);
        };
        let own = 1.0 - LOBE_SHARE;
        let from_lobe = u.x >= own;
        let s = if !from_lobe {
            self.sample_light(light, at, Vec2::new(u.x / own, u.y))?
        } else {
            let ray = Ray { origin: at.p, dir: lobe.sample(Vec2::new((u.x - own) / LOBE_SHARE, u.y))? };
            let distance = shape.intersect(&ray, 0.0, f32::INFINITY)?;
            let y = SurfacePoint { p: ray.at(distance), n: shape.normal_at(ray.at(distance)) };
            if !(dot(y.n, ray.dir) < 0.0) {
                return None; // the back of a quad: it emits nothing that way
            }
            let pdf = self.pdf_light(light, at, &y);
            LightSample { wi: ray.dir, distance, radiance, pdf, delta: false, emitter: Some(emitter) }
        };
        let lobe_pdf = lobe.pdf(s.wi);
        // A lobe sample on its box's side, which the direction's rounding put just outside: no
        // sample (its pdf would be the light's part alone, and its weight a spike).
        if from_lobe && !(lobe_pdf > 0.0) {
            return None;
        }
        let pdf = own * s.pdf + LOBE_SHARE * lobe_pdf;
        positive_finite(pdf).then_some(LightSample { pdf, ..s })
    }

    /// Pdf per unit solid angle at the shading point `at` with which [`LightSampler::sample`]
    /// draws the direction to the point `y` of `light` (found by a BSDF ray), selection not
    /// included; 0 for point lights.
    #[inline]
    pub fn pdf(&self, light: LightId, at: &ShadingPoint, y: &SurfacePoint) -> f32 {
        let own = self.pdf_light(light, at, y);
        let Some((lobe, ..)) = self.lobe_towards(light, at) else { return own };
        let v = y.p - at.p;
        let d2 = dot(v, v);
        if !(d2 > 0.0) {
            return 0.0;
        }
        (1.0 - LOBE_SHARE) * own + LOBE_SHARE * lobe.pdf(v / sqrt(d2))
    }

    /// The receiver's lobe towards the area light `light` (with its shape, radiance and
    /// emitting shape), where [`LobeMixing::On`] applies at `at` ([`Lobe::towards`]).
    #[inline(always)]
    fn lobe_towards(&self, light: LightId, at: &ShadingPoint) -> Option<(Lobe, &'a Shape, Rgb, ShapeId)> {
        if !LobeMixing::AVAILABLE || self.lobe != LobeMixing::On {
            return None;
        }
        let light = self.scene.light(light)?;
        let Light::Area { radiance, shape: emitter } = *light else { return None };
        let shape = self.scene.light_shape(light)?;
        let lobe = Lobe::towards(shape, at.p, at.n, at.wo, &at.bsdf)?;
        Some((lobe, shape, radiance, emitter))
    }

    /// A point on `light` drawn by the light's own strategy (spheres by area or cone, quads by
    /// area or solid angle).
    #[inline]
    fn sample_light(&self, light: LightId, at: &ShadingPoint, u: Vec2) -> Option<LightSample> {
        let x = at.p;
        let light = self.scene.light(light)?;
        let shape = self.scene.light_shape(light);
        if let (Light::Area { radiance, shape: emitter }, Some(shape)) = (light, shape) {
            if let Some((rect, sr)) = rectangle_seen_from(shape, x, self.quads) {
                // Decided by the setup alone, as in `pdf`: no fallback after this point.
                let s = sample_rectangle(&rect, &sr, self.quads, at.n, u)?;
                return Some(LightSample { radiance: *radiance, emitter: Some(*emitter), ..s });
            }
        }
        light.sample_li(shape, x, u, self.spheres)
    }

    /// The pdf of [`LightSampler::sample_light`] drawing the direction to `y`.
    #[inline]
    fn pdf_light(&self, light: LightId, at: &ShadingPoint, y: &SurfacePoint) -> f32 {
        let x = at.p;
        match self.scene.light(light) {
            Some(light) => {
                let shape = self.scene.light_shape(light);
                if let (Light::Area { .. }, Some((rect, sr))) =
                    (light, shape.and_then(|s| rectangle_seen_from(s, x, self.quads)))
                {
                    return rectangle_pdf(&rect, &sr, self.quads, at, y.p);
                }
                light.pdf_li(shape, x, y, self.spheres)
            }
            None => 0.0,
        }
    }
}

/// The spherical rectangle a rectangular quad light subtends at `x`, when quads are sampled in
/// solid angle and f32 can resolve it (else the light is sampled by area). The setting's test
/// stays inline (it is the same for the whole render); the rest may go out of line.
#[inline(always)]
fn rectangle_seen_from(
    shape: &Shape,
    x: Vec3,
    quads: QuadSampling,
) -> Option<(Rectangle, SphericalRectangle)> {
    if quads == QuadSampling::Area {
        return None;
    }
    rectangle_in_solid_angle(shape, x)
}

/// [`rectangle_seen_from`] when quads are sampled in solid angle.
#[inline]
fn rectangle_in_solid_angle(shape: &Shape, x: Vec3) -> Option<(Rectangle, SphericalRectangle)> {
    let rect = shape.as_rectangle()?;
    let d = rect.p0 - x;
    let corner = Vec3::new(d.dot(rect.ex), d.dot(rect.ey), d.dot(rect.n));
    Some((rect, spherical_rectangle(corner, rect.lengths.x, rect.lengths.y)?))
}

/// The corner weights of the cosine warp for a receiver with unit normal `n` (world).
#[inline]
fn cosine_weights(rect: &Rectangle, sr: &SphericalRectangle, n: Vec3) -> [f32; 4] {
    spherical_rectangle_cosines(sr, Vec3::new(n.dot(rect.ex), n.dot(rect.ey), n.dot(rect.n)))
}

/// A direction to the rectangle `rect` (seen as `sr`) from a receiver with unit normal `n`, in
/// solid angle, first warped by the cosine for [`QuadSampling::SolidAngleCosine`]; radiance and
/// emitter are left for the caller. Out of line, like [`rectangle_pdf`]: one copy in the
/// firmware, and the code of spheres and points does not grow.
#[inline(never)]
fn sample_rectangle(
    rect: &Rectangle,
    sr: &SphericalRectangle,
    quads: QuadSampling,
    n: Vec3,
    u: Vec2,
) -> Option<LightSample> {
    let (u, warp_pdf) = match quads {
        QuadSampling::SolidAngleCosine => {
            let w = cosine_weights(rect, sr, n);
            let v = sample_bilinear(u, w);
            (v, bilinear_pdf(v, w))
        }
        _ => (u, 1.0),
    };
    let local = sample_spherical_rectangle(sr, u)?;
    let distance = sqrt(local.length_squared());
    let wi = (rect.ex * local.x + rect.ey * local.y + rect.n * local.z) / distance;
    let pdf = spherical_rectangle_pdf(sr) * warp_pdf;
    (distance > 0.0 && pdf.is_finite()).then_some(LightSample::towards(wi, distance, pdf))
}

/// The pdf with which [`sample_rectangle`] reaches the point `y` of the rectangle from the
/// shading point `at`: 1 / solid angle, times the bilinear pdf of the u that reaches `y` for
/// [`QuadSampling::SolidAngleCosine`].
#[inline(never)]
fn rectangle_pdf(
    rect: &Rectangle,
    sr: &SphericalRectangle,
    quads: QuadSampling,
    at: &ShadingPoint,
    y: Vec3,
) -> f32 {
    let pdf = spherical_rectangle_pdf(sr);
    match quads {
        QuadSampling::SolidAngleCosine => {
            let v = y - at.p;
            let local = Vec3::new(v.dot(rect.ex), v.dot(rect.ey), v.dot(rect.n));
            pdf * bilinear_pdf(invert_spherical_rectangle_sample(sr, local), cosine_weights(rect, sr, at.n))
        }
        _ => pdf,
    }
}

impl Light {
    /// Draws a point on the light as seen from `x`. `shape` is the emitting shape of an area
    /// light (ignored for point lights). `None` when the sample carries no light (a point on the
    /// far side of a sphere, behind a quad, or a point light at `x`).
    #[inline]
    pub fn sample_li(
        &self,
        shape: Option<&Shape>,
        x: Vec3,
        u: Vec2,
        spheres: SphereSampling,
    ) -> Option<LightSample> {
        match *self {
            Light::Point { position, intensity } => {
                let v = position - x;
                let d2 = dot(v, v);
                if !(d2 > 0.0) {
                    return None;
                }
                let distance = sqrt(d2);
                Some(LightSample {
                    wi: v / distance,
                    distance,
                    radiance: intensity / d2,
                    pdf: 1.0,
                    delta: true,
                    emitter: None,
                })
            }
            Light::Area { radiance, shape: emitter } => {
                let shape = shape?;
                let emitter = Some(emitter);
                if let (SphereSampling::Cone, Some((center, r))) = (spheres, shape.as_sphere()) {
                    if let Some(s) = sample_sphere_cone(center, r, x, u) {
                        return Some(LightSample { radiance, emitter, ..s });
                    }
                }
                // Uniform area, converted to solid angle: p_w = p_A |x - y|^2 / cos(theta_y).
                let y = shape.sample_area(u);
                let pdf = area_to_solid_angle(shape.area_pdf(), x, &y)?;
                let v = y.p - x;
                let distance = sqrt(dot(v, v));
                Some(LightSample { wi: v / distance, distance, radiance, pdf, delta: false, emitter })
            }
        }
    }

    /// Pdf per unit solid angle with which [`Light::sample_li`] produces the direction from `x`
    /// to the point `y` of this light's shape (found by a BSDF ray); 0 for point lights.
    #[inline]
    pub fn pdf_li(&self, shape: Option<&Shape>, x: Vec3, y: &SurfacePoint, spheres: SphereSampling) -> f32 {
        match (self, shape) {
            (Light::Point { .. }, _) | (Light::Area { .. }, None) => 0.0,
            (Light::Area { .. }, Some(shape)) => {
                if let (SphereSampling::Cone, Some((center, r))) = (spheres, shape.as_sphere()) {
                    if let Some(omc) = sphere_cone(center, r, x) {
                        return uniform_cone_pdf(omc);
                    }
                }
                area_to_solid_angle(shape.area_pdf(), x, y).unwrap_or(0.0)
            }
        }
    }
}

/// Converts an area pdf at `y` to solid angle at `x`; `None` where `y` faces away from `x`.
#[inline]
fn area_to_solid_angle(pdf_area: f32, x: Vec3, y: &SurfacePoint) -> Option<f32> {
    let v = x - y.p;
    let d2 = dot(v, v);
    let cos_y = dot(y.n, v);
    // cos_y here is unnormalized (times |v|): pdf = p_A d^2 / (cos_y / d) = p_A d^3 / cos_y'.
    if !(cos_y > 0.0) || !(d2 > 0.0) {
        return None;
    }
    let pdf = pdf_area * d2 * sqrt(d2) / cos_y;
    pdf.is_finite().then_some(pdf)
}

/// `1 - cos(theta_max)` of the cone a sphere subtends from `x`; `None` from inside or on it.
#[inline]
fn sphere_cone(center: Vec3, radius: f32, x: Vec3) -> Option<f32> {
    let to_center = center - x;
    let d2 = dot(to_center, to_center);
    let r2 = radius * radius;
    (d2 > r2).then(|| cone_one_minus_cos(r2 / d2))
}

/// Uniform direction in the cone a sphere subtends, and the near point it hits.
#[inline]
fn sample_sphere_cone(center: Vec3, radius: f32, x: Vec3, u: Vec2) -> Option<LightSample> {
    let omc = sphere_cone(center, radius, x)?;
    let to_c = center - x;
    let d2 = dot(to_c, to_c);
    let d = sqrt(d2);
    let local = sample_uniform_cone(u, omc);
    let wi = from_local_around(to_c * (1.0 / d), local);
    // Distance to the near intersection: d cos(theta) - sqrt(r^2 - d^2 sin^2(theta)).
    let sin2 = local.x * local.x + local.y * local.y;
    let distance = max0(d * local.z - safe_sqrt(radius * radius - d2 * sin2));
    let pdf = uniform_cone_pdf(omc);
    positive_finite(pdf).then_some(LightSample::towards(wi, distance, pdf))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Film, test_desc};
    use crate::scene::Material;

    fn scene() -> Scene<2, 3, 1> {
        let cam = test_desc(40.0);
        let mut s: Scene<2, 3, 1> = Scene::new(cam, Film::new(4, 4).unwrap()).unwrap();
        let m = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
        let a = s.add_shape(Shape::sphere(Vec3::ZERO, 1.0).unwrap(), m).unwrap();
        s.add_area_light(a, Rgb::splat(2.0)).unwrap();
        s.add_point_light(Vec3::ONE, Rgb::splat(1.0)).unwrap();
        s.add_point_light(Vec3::ONE, Rgb::ZERO).unwrap();
        s
    }

    #[test]
    fn selection_probabilities_sum_to_one_and_are_realised() {
        let s = scene();
        let bsdf = Material::lambertian(Rgb::ONE).unwrap();
        // Facing down: the sphere light and the bright point light are above its horizon.
        let point = ShadingPoint { p: Vec3::new(0.0, 3.0, 0.0), n: -Vec3::Y, wo: -Vec3::Y, bsdf };
        for sel in LightSelection::ALL {
            let lights = LightSampler::new(&s, sel, SphereSampling::Cone);
            let at = lights.selection_at(&point);
            let sum: f32 = (0..3).map(|i| lights.pmf(&at, LightId::new(i))).sum();
            assert!((sum - 1.0).abs() < 1e-6);
            assert_eq!(lights.pmf(&at, LightId::new(3)), 0.0);
            // Never selects a light with zero selection probability.
            for k in 0..1000 {
                let c = lights.select(&at, k as f32 / 1000.0).unwrap();
                assert!(c.probability > 0.0 && c.probability == lights.pmf(&at, c.light));
            }
        }
    }

    #[test]
    fn selection_names_round_trip() {
        for s in LightSelection::ALL {
            assert_eq!(LightSelection::from_name(s.name()), Some(s));
        }
        assert_eq!(LightSelection::from_name("random"), None);
        assert_eq!(LightSelection::ALL[0], LightSelection::default());
    }

    #[test]
    fn samples_name_their_emitter_and_exclude_selection() {
        let s = scene();
        let lights = LightSampler::new(&s, LightSelection::Power, SphereSampling::Cone);
        let x = Vec3::new(0.0, 3.0, 0.0);
        let at =
            ShadingPoint { p: x, n: Vec3::Y, wo: Vec3::Y, bsdf: Material::lambertian(Rgb::ONE).unwrap() };
        let ls = lights.sample(LightId::new(0), &at, Vec2::new(0.3, 0.6)).unwrap();
        assert_eq!(ls.emitter, Some(ShapeId::new(0)));
        let y = SurfacePoint { p: x + ls.wi * ls.distance, n: (x + ls.wi * ls.distance).normalize() };
        assert_eq!(lights.pdf(LightId::new(0), &at, &y), ls.pdf);
        let point = lights.sample(LightId::new(1), &at, Vec2::new(0.3, 0.6)).unwrap();
        assert!(point.delta && point.emitter.is_none() && point.pdf == 1.0);
        assert!(lights.sample(LightId::new(9), &at, Vec2::ZERO).is_none());
        assert_eq!(lights.pdf(LightId::new(9), &at, &y), 0.0);
    }
}
