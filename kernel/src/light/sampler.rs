//! The light sampler: light sampling's one home. It chooses a light for a light sample (its
//! [`Select`] strategy) and draws a direction to a point on it (spheres by their
//! [`SphereSampler`], quads by their [`QuadSampler`], either also from a glossy receiver's lobe
//! by the [`LobeSampler`]), and it evaluates the probabilities of what it drew, as pairs:
//!
//! - [`LightSampler::select`] / [`LightSampler::pmf`]: the light and its selection probability
//!   P(light) at a shading point, both read from the selection there
//!   ([`LightSampler::selection_at`], computed once per shading point), so they cannot disagree;
//! - [`LightSampler::sample`] / [`LightSampler::pdf`]: the light sample and its pdf per unit solid
//!   angle at `x`, p_w(wi | light), selection not included ([`LightSample::pdf`]).
//!
//! The light technique's pdf is their product, p_l = P(light) p_w, and the estimator writes it so.
//! The strategies are types ([`LightStrategies`]), chosen once: a build carries only those it names.

use core::marker::PhantomData;

use crate::geometry::{Ray, Shape, SurfacePoint};
use crate::light::lobe::{LOBE_SHARE, Lobe, LobeMixing, LobeSampler};
use crate::light::quad::QuadSampler;
use crate::light::sample::{LightChoice, LightSample, ShadingPoint};
use crate::light::select::{Residual, Select};
use crate::light::sphere::SphereSampler;
use crate::num::{Frame, Rgb, Vec2, Vec3, dot, positive_finite, sqrt};
use crate::sampling::GRID;
use crate::scene::{Light, LightId, Outgoing, Scene, ShapeId};

/// The light strategies of a render, as types: how a light is chosen, how sphere and quad lights
/// are sampled, and whether a glossy receiver's lobe joins the light samples. `L` is the scene's
/// light capacity (the selection's tables are sized by it).
pub trait LightStrategies<const L: usize>: 'static {
    /// How a light is chosen.
    type Selection: Select<L>;
    /// How points on sphere lights are drawn.
    type Spheres: SphereSampler;
    /// How points on quad lights are drawn.
    type Quads: QuadSampler;
    /// Whether a glossy receiver's lobe joins the light samples.
    type Lobe: LobeSampler;
}

/// The light strategies `Sel`, `Sp`, `Q` and `Lb` as one type.
pub struct Lights<Sel, Sp, Q, Lb>(PhantomData<Types<(Sel, Sp, Q, Lb)>>);

/// The types of a strategy bundle (a function type: the bundle is `Send`, `Sync` and `Copy`
/// whatever they are).
type Types<T> = fn() -> T;

impl<const L: usize, Sel: Select<L>, Sp: SphereSampler, Q: QuadSampler, Lb: LobeSampler> LightStrategies<L>
    for Lights<Sel, Sp, Q, Lb>
{
    type Selection = Sel;
    type Spheres = Sp;
    type Quads = Q;
    type Lobe = Lb;
}

/// What a light's selection reads at one shading point.
pub type SelectionAt<St, const L: usize> = <<St as LightStrategies<L>>::Selection as Select<L>>::At;

/// Light sampling in one scene with the strategies `St`.
pub struct LightSampler<'a, St: LightStrategies<L>, const S: usize, const L: usize, const M: usize> {
    scene: &'a Scene<S, L, M>,
    selection: St::Selection,
}

impl<'a, St: LightStrategies<L>, const S: usize, const L: usize, const M: usize>
    LightSampler<'a, St, S, L, M>
{
    /// The sampler of `scene`'s lights (its selection's tables are built here, once).
    pub fn new(scene: &'a Scene<S, L, M>) -> Self {
        Self { scene, selection: St::Selection::new(scene) }
    }

    /// The scene.
    #[inline]
    pub fn scene(&self) -> &'a Scene<S, L, M> {
        self.scene
    }

    /// Light selection at `at` (computed once per shading point; see [`Select::at`]).
    pub fn selection_at(&self, at: &ShadingPoint) -> SelectionAt<St, L> {
        let frame = Frame::from_normal(at.n);
        self.selection_in(at, &frame, &at.bsdf.seen_from(frame.to_local(at.wo)), Residual::default())
    }

    /// [`LightSampler::selection_at`] given the receiver's frame (from its normal,
    /// [`Frame::from_normal`]) and its BSDF `seen` from `at.wo` in it, which the caller has
    /// already computed, and what the control variate leaves to sampling there (see
    /// [`Select::at`]).
    #[inline]
    pub fn selection_in(
        &self,
        at: &ShadingPoint,
        frame: &Frame,
        seen: &Outgoing,
        residual: Residual,
    ) -> SelectionAt<St, L> {
        self.selection.at(at, frame, seen, residual)
    }

    /// Chooses a light at the shading point of `at` with the random number `u` in [0, 1) (on the
    /// 2^24 grid of [`Sampler::next_f32`](crate::sampling::Sampler::next_f32)); `None` when the
    /// scene has no light (or, selecting by contribution, no light can contribute there).
    #[inline]
    pub fn select(&self, at: &SelectionAt<St, L>, u: f32) -> Option<LightChoice> {
        let k = ((u * GRID as f32) as u32).min(GRID - 1);
        self.select_reusing(at, k << 8).map(|(chosen, _)| chosen)
    }

    /// Chooses a light like [`LightSampler::select`] with the top 24 of the 32 random `bits`, and
    /// returns with it the bits rescaled within the chosen light's share (see [`Select::select`]).
    #[inline]
    pub fn select_reusing(&self, at: &SelectionAt<St, L>, bits: u32) -> Option<(LightChoice, f32)> {
        self.selection.select(at, bits)
    }

    /// The probability with which [`LightSampler::select`] chooses `light` at the shading point
    /// of `at`.
    #[inline]
    pub fn pmf(&self, at: &SelectionAt<St, L>, light: LightId) -> f32 {
        if light.index() >= self.scene.lights().len() {
            return 0.0;
        }
        self.selection.pmf(at, light)
    }

    /// Draws a point on `light` as seen from the shading point `at` with the random numbers `u`;
    /// `None` when the sample carries no light (a point on the far side of a sphere, behind a
    /// quad, or a point light at `x`) or the scene has no such light. Where the receiver's lobe
    /// joins the light samples ([`LobeSampler`]), a share of them ([`LOBE_SHARE`], by `u.x`,
    /// rescaled) comes from the lobe instead, and the pdf is the mixture's.
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
    /// emitting shape), where it joins the light samples at `at`.
    #[inline(always)]
    fn lobe_towards(&self, light: LightId, at: &ShadingPoint) -> Option<(Lobe, &'a Shape, Rgb, ShapeId)> {
        if let LobeMixing::Off = St::Lobe::KIND {
            return None;
        }
        let light = self.scene.light(light)?;
        let Light::Area { radiance, shape: emitter } = *light else { return None };
        let shape = self.scene.light_shape(light)?;
        let lobe = St::Lobe::towards::<St::Spheres, St::Quads>(shape, at)?;
        Some((lobe, shape, radiance, emitter))
    }

    /// A point on `light` drawn by the light's own strategy.
    #[inline]
    fn sample_light(&self, light: LightId, at: &ShadingPoint, u: Vec2) -> Option<LightSample> {
        let x = at.p;
        match *self.scene.light(light)? {
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
                let shape = self.scene.light_shape(self.scene.light(light)?)?;
                let s = self.sample_shape(shape, at, u)?;
                Some(LightSample { radiance, emitter: Some(emitter), ..s })
            }
        }
    }

    /// A direction to a point of the emitting `shape` (radiance and emitter left for the caller):
    /// by the sphere or quad strategy where it applies, else uniformly by area, converted to solid
    /// angle, p_w = p_A |x - y|^2 / cos(theta_y).
    #[inline]
    fn sample_shape(&self, shape: &Shape, at: &ShadingPoint, u: Vec2) -> Option<LightSample> {
        let x = at.p;
        if let Some((rect, sr)) = St::Quads::seen(shape, at) {
            // Decided by the setup alone, as in `pdf`: no fallback after this point.
            return St::Quads::sample(&rect, &sr, at, u);
        }
        if let Some((center, radius)) = shape.as_sphere() {
            if let Some(s) = St::Spheres::sample(center, radius, x, u) {
                return Some(s);
            }
        }
        let y = shape.sample_area(u);
        let pdf = area_to_solid_angle(shape.area_pdf(), x, &y)?;
        let v = y.p - x;
        let distance = sqrt(dot(v, v));
        Some(LightSample::towards(v / distance, distance, pdf))
    }

    /// The pdf of [`LightSampler::sample_light`] drawing the direction to `y`.
    #[inline]
    fn pdf_light(&self, light: LightId, at: &ShadingPoint, y: &SurfacePoint) -> f32 {
        let x = at.p;
        let Some(light @ Light::Area { .. }) = self.scene.light(light) else { return 0.0 };
        let Some(shape) = self.scene.light_shape(light) else { return 0.0 };
        if let Some((rect, sr)) = St::Quads::seen(shape, at) {
            return St::Quads::pdf(&rect, &sr, at, y.p);
        }
        if let Some((center, radius)) = shape.as_sphere() {
            if let Some(pdf) = St::Spheres::pdf(center, radius, x) {
                return pdf;
            }
        }
        area_to_solid_angle(shape.area_pdf(), x, y).unwrap_or(0.0)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Film, test_desc};
    use crate::light::select::{ByContribution, ByPower, Uniform};
    use crate::light::{lobe, quad, sphere};
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
        fn check<Sel: Select<3>>(s: &Scene<2, 3, 1>, point: &ShadingPoint) {
            let lights =
                LightSampler::<Lights<Sel, sphere::InCone, quad::ByArea, lobe::Off>, 2, 3, 1>::new(s);
            let at = lights.selection_at(point);
            let sum: f32 = (0..3).map(|i| lights.pmf(&at, LightId::new(i))).sum();
            assert!((sum - 1.0).abs() < 1e-6);
            assert_eq!(lights.pmf(&at, LightId::new(3)), 0.0);
            // Never selects a light with zero selection probability.
            for k in 0..1000 {
                let c = lights.select(&at, k as f32 / 1000.0).unwrap();
                assert!(c.probability > 0.0 && c.probability == lights.pmf(&at, c.light));
            }
        }
        check::<Uniform>(&s, &point);
        check::<ByPower<3>>(&s, &point);
        check::<ByContribution<3>>(&s, &point);
    }

    #[test]
    fn selection_names_round_trip() {
        for s in crate::light::LightSelection::ALL {
            assert_eq!(crate::light::LightSelection::from_name(s.name()), Some(s));
        }
        assert_eq!(crate::light::LightSelection::from_name("random"), None);
    }

    #[test]
    fn samples_name_their_emitter_and_exclude_selection() {
        let s = scene();
        let lights =
            LightSampler::<Lights<ByPower<3>, sphere::InCone, quad::ByArea, lobe::Off>, 2, 3, 1>::new(&s);
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
