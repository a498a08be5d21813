//! The MIS direct-lighting estimator of the lecture (Veach and Guibas 1995), multi-sample model
//! (and the one-sample model of section 4, see [`crate::integrator::model`]):
//!
//! F = 1/n_l sum_j w_l(X_j) f(X_j)/p_l(X_j) + 1/n_b sum_j w_b(Y_j) f(Y_j)/p_b(Y_j),
//!
//! with f = L_e f_r cos(theta_i) over directions at the shading point, p_l = P(light) p_w the light
//! technique's pdf (the light sampler's selection probability times its pdf per unit solid angle),
//! p_b the BSDF's pdf, and w the weights of [`Method`] on q_i = n_i p_i. Each technique's weighted
//! contribution and weights are kept apart, so the lecture's weight and contribution images come
//! from this one estimator. It is built for one set of strategies ([`Strategies`]), chosen once.

use crate::error::SceneError;
use crate::geometry::Ray;
use crate::integrator::closed_form::{self, Cover, Covered};
use crate::integrator::control_variate::ControlVariateStrategy;
use crate::integrator::estimate::{Estimate, TechniqueEstimate};
use crate::integrator::mis::{Method, Technique};
use crate::integrator::model::Model;
use crate::integrator::settings::{RenderSettings, SettingsSource};
use crate::integrator::strategies::Strategies;
use crate::light::{LightChoice, LightSampler, LightStrategies, Residual, Select, SelectionAt, ShadingPoint};
use crate::num::{Frame, Rgb, Vec3};
use crate::query::accel::{POINT_TERMS, PointRays};
use crate::sampling::Sampler;
use crate::scene::{Hit, Light, LightId, Material, Outgoing, Scene};

/// The estimator for one scene, one render's settings and their strategies `St`.
pub struct Integrator<'a, St: Strategies<L>, const S: usize, const L: usize, const M: usize> {
    scene: &'a Scene<S, L, M>,
    /// By reference: a firmware's settings are a `static` whose values the compiler folds into
    /// the code (the loops over sample counts, the sample stream), which a copy would hide.
    settings: &'a RenderSettings,
    lights: LightSampler<'a, St::Lights, S, L, M>,
    /// The lights the `auto` control variate covers in this scene.
    auto_cover: Cover,
}

/// The light sampler of the strategies `St`.
type Lights<'a, St, const S: usize, const L: usize, const M: usize> =
    LightSampler<'a, <St as Strategies<L>>::Lights, S, L, M>;

impl<'a, St: Strategies<L>, const S: usize, const L: usize, const M: usize> Integrator<'a, St, S, L, M> {
    /// The estimator of `scene` with `settings`, which must name the strategies `St`
    /// ([`SceneError::StrategyMismatch`] otherwise). Light selection's tables are built here.
    pub fn new(scene: &'a Scene<S, L, M>, settings: &'a RenderSettings) -> Result<Self, SceneError> {
        St::check(settings)?;
        Ok(Self {
            scene,
            settings,
            lights: LightSampler::new(scene),
            auto_cover: Cover::auto::<St::ControlVariate, S, L, M>(scene),
        })
    }

    /// The scene.
    #[inline]
    pub fn scene(&self) -> &'a Scene<S, L, M> {
        self.scene
    }

    /// The settings (those it was built with, or the strategies' constant ones: the same values).
    #[inline(always)]
    pub fn settings(&self) -> RenderSettings {
        St::Settings::settings(self.settings)
    }

    /// The light sampler.
    #[inline]
    pub fn lights(&self) -> &Lights<'a, St, S, L, M> {
        &self.lights
    }

    /// The combination method.
    #[inline(always)]
    fn method(&self) -> Method {
        self.settings().method()
    }

    /// Radiance arriving along a camera ray: emission of the first hit plus its direct lighting.
    #[inline]
    pub fn trace(&self, ray: &Ray, t_near: f32, sampler: &mut Sampler) -> Estimate {
        self.shade(self.scene.intersect(ray, t_near, f32::INFINITY, None), ray.dir, sampler)
    }

    /// Radiance arriving along a ray in direction `dir` whose first hit is `hit` ([`Self::trace`]
    /// once the ray is traced): emission plus direct lighting.
    #[inline]
    pub fn shade(&self, hit: Option<Hit>, dir: Vec3, sampler: &mut Sampler) -> Estimate {
        let Some(hit) = hit else {
            return Estimate::default();
        };
        if !hit.front {
            return Estimate::default(); // one-sided: nothing is emitted or reflected towards the back
        }
        let emitted = match self.scene.emitter(hit.object) {
            Some((_, Light::Area { radiance, .. })) => *radiance,
            _ => Rgb::ZERO,
        };
        let (light, bsdf) = self.estimate_direct(&hit, -dir, sampler);
        Estimate { emitted, light, bsdf }
    }

    /// Direct lighting at `x` towards `wo`, by light sampling and BSDF sampling combined with
    /// MIS, in the strategies' model: [`Self::estimate_direct_multi_sample`] or
    /// [`Self::estimate_direct_one_sample`]. With the control variate, a Lambertian receiver
    /// gets the unoccluded light of every quad and sphere light in closed form, in the light
    /// part, and the techniques sample only f (V - 1) for those lights.
    #[inline]
    pub fn estimate_direct(
        &self,
        x: &Hit,
        wo: Vec3,
        sampler: &mut Sampler,
    ) -> (TechniqueEstimate, TechniqueEstimate) {
        let none = (TechniqueEstimate::default(), TechniqueEstimate::default());
        // On the microcontrollers not through `shading`, whose `Option` costs a copy of the
        // struct on the M4F. On x86 the other way round: that struct built by a function of its
        // own makes the render slower.
        #[cfg(target_os = "none")]
        let at = match reflecting(self.scene, x) {
            Some(bsdf) => shading!(self, x, bsdf, wo),
            None => return none,
        };
        #[cfg(not(target_os = "none"))]
        let Some(at) = self.shading(x, wo) else { return none };
        if at.all_exact {
            let mut by_light = TechniqueEstimate::default();
            by_light.contribution += at.unoccluded;
            return (by_light, TechniqueEstimate::default());
        }
        let (mut by_light, by_bsdf) = if St::Model::ONE_SAMPLE {
            self.estimate_direct_one_sample(&at, sampler)
        } else {
            self.estimate_direct_multi_sample(&at, sampler)
        };
        // The closed-form part of the control variate (zero without it).
        by_light.contribution += at.unoccluded;
        (by_light, by_bsdf)
    }

    /// The shading point `x` seen from `wo`; `None` when its material reflects nothing.
    #[inline]
    pub fn shading<'h>(&'h self, x: &'h Hit, wo: Vec3) -> Option<Shading<'h, St, L>> {
        let bsdf = reflecting(self.scene, x)?;
        Some(shading!(self, x, bsdf, wo))
    }

    /// The multi-sample model: F = sum_i 1/n_i sum_j w_i(X_ij) f(X_ij) / p_i(X_ij), q_i = n_i p_i.
    #[inline]
    pub fn estimate_direct_multi_sample(
        &self,
        at: &Shading<'_, St, L>,
        sampler: &mut Sampler,
    ) -> (TechniqueEstimate, TechniqueEstimate) {
        let (mut by_light, mut by_bsdf) = (TechniqueEstimate::default(), TechniqueEstimate::default());
        let (n_l, n_b) = self.settings().technique_samples();
        let (n_light, n_bsdf) = (f32::from(n_l), f32::from(n_b));
        // Shadow and BSDF rays all start at x: what their tests need of x alone, computed once.
        at.with_rays(self.scene, |from_x| {
            // Technique 1, light sampling: a light, y on it, visibility, w_l L_e f cos / (n_l p_l).
            for _ in 0..n_l {
                self.light_samples(at, from_x, sampler, |s| {
                    add_light_sample(&mut by_light, self.method(), &s, n_light, n_bsdf)
                });
            }

            // Technique 2, BSDF sampling: wi ~ p_b, trace; if a light's front side is hit,
            // w_b L_e f cos / (n_b p_b), with p_l evaluated for the light that was hit.
            for _ in 0..n_b {
                // (The method is read in here, not captured: a constant method stays a constant.)
                self.bsdf_sample(at, from_x, sampler, |s| {
                    add_bsdf_sample(&mut by_bsdf, self.method(), &s, n_light, n_bsdf)
                });
            }
        });
        (by_light, by_bsdf)
    }

    /// The one-sample model: pick the light technique with probability c_l (else the BSDF
    /// technique, c_b = 1 - c_l), draw one sample X from it, F = w_i(X) f(X) / (c_i p_i(X)),
    /// q_i = c_i p_i. (Out of line: its rays from x do not add to the stack frame of the
    /// multi-sample model's.)
    #[inline(never)]
    pub fn estimate_direct_one_sample(
        &self,
        at: &Shading<'_, St, L>,
        sampler: &mut Sampler,
    ) -> (TechniqueEstimate, TechniqueEstimate) {
        let (mut by_light, mut by_bsdf) = (TechniqueEstimate::default(), TechniqueEstimate::default());
        let c_light = self.settings().c_light();
        let c_bsdf = 1.0 - c_light;
        // The multi-sample formulas with n_i replaced by c_i, for one sample of one technique.
        at.with_rays(self.scene, |from_x| {
            if sampler.next_f32() < c_light {
                self.light_samples(at, from_x, sampler, |s| {
                    add_light_sample(&mut by_light, self.method(), &s, c_light, c_bsdf)
                });
            } else {
                self.bsdf_sample(at, from_x, sampler, |s| {
                    add_bsdf_sample(&mut by_bsdf, self.method(), &s, c_light, c_bsdf)
                });
            }
        });
        (by_light, by_bsdf)
    }

    /// The light samples of one draw, each passed to `found`: the light the selection chooses,
    /// or, with a selection that takes every light ([`Select::EVERY`]), each light in turn
    /// ([`Self::every_light_sample`]).
    #[inline(always)]
    fn light_samples(
        &self,
        at: &Shading<'_, St, L>,
        from_x: &PointRays<S>,
        sampler: &mut Sampler,
        mut found: impl FnMut(Found),
    ) {
        if <<St::Lights as LightStrategies<L>>::Selection as Select<L>>::EVERY {
            self.every_light_sample(at, from_x, sampler, found);
        } else if let Some(s) = self.light_sample(at, from_x, sampler) {
            found(s);
        }
    }

    /// One sample of every light that is not exact here, all with the same random numbers, each
    /// with probability one. (Out of line: a firmware that carries it shows it by name.)
    #[inline(never)]
    fn every_light_sample(
        &self,
        at: &Shading<'_, St, L>,
        from_x: &PointRays<S>,
        sampler: &mut Sampler,
        mut found: impl FnMut(Found),
    ) {
        let (bits, v) = sampler.next_2d_reusable();
        let u = crate::sampling::sampler::to_unit(bits);
        for k in 0..self.scene.lights().len() {
            let light = LightId::new(k as u16);
            let probability = self.lights.pmf(&at.selection, light);
            if probability > 0.0 {
                let chosen = LightChoice { light, probability };
                if let Some(s) = self.light_sample_on(at, from_x, chosen, crate::num::Vec2::new(u, v)) {
                    found(s);
                }
            }
        }
    }

    /// One light sample: a light and a point on it, f L_e, with V (or V - 1 for a light in
    /// closed form); `None` when it carries nothing.
    #[inline]
    fn light_sample(
        &self,
        at: &Shading<'_, St, L>,
        from_x: &PointRays<S>,
        sampler: &mut Sampler,
    ) -> Option<Found> {
        // One 2-D request: its first number chooses the light and, rescaled, places the point.
        let (u_select, v) = sampler.next_2d_reusable();
        let (chosen, u) = self.lights.select_reusing(&at.selection, u_select)?;
        self.light_sample_on(at, from_x, chosen, crate::num::Vec2::new(u, v))
    }

    /// A light sample of the light `chosen` with the random numbers `u`.
    #[inline(always)]
    fn light_sample_on(
        &self,
        at: &Shading<'_, St, L>,
        from_x: &PointRays<S>,
        chosen: LightChoice,
        u: crate::num::Vec2,
    ) -> Option<Found> {
        let ls = self.lights.sample(chosen.light, &at.point, u)?;
        // The light technique's pdf of this direction: p_l = P(light) p_w(wi | light).
        let p_light = chosen.probability * ls.pdf;
        let wi = at.bsdf.to_local(&at.frame, ls.wi);
        let (f, p_bsdf) = at.seen.eval_pdf(wi);
        if f == Rgb::ZERO || ls.radiance == Rgb::ZERO {
            return None;
        }
        let visible = self.scene.unoccluded_from(
            from_x,
            ls.wi,
            ls.distance,
            at.x.object,
            ls.emitter,
            Some(chosen.light),
        );
        let value = match (at.analytic(chosen.light), visible) {
            (false, true) => f * ls.radiance,
            (true, false) => -(f * ls.radiance),
            (false, false) | (true, true) => return None,
        };
        Some(Found { value, pdf: p_light, pdf_other: p_bsdf, delta: ls.delta })
    }

    /// One BSDF sample: wi ~ p_b, traced; `found` is called for each light it counts for, with
    /// f L_e / p_b. Without the control variate that is the first surface, if it is a light's
    /// front side. With it, a light in closed form counts with f L_e (V - 1) / p_b: only when the
    /// ray meets its front side behind another surface.
    ///
    /// Out of line (inlined into the multi-sample model's loop, its loop-invariant values are
    /// spilled around it on the M4F), except on RV32IMC, where its own frame would add to the
    /// peak stack.
    #[cfg_attr(not(target_arch = "riscv32"), inline(never))]
    #[cfg_attr(target_arch = "riscv32", inline)]
    fn bsdf_sample(
        &self,
        at: &Shading<'_, St, L>,
        from_x: &PointRays<S>,
        sampler: &mut Sampler,
        mut found: impl FnMut(Found),
    ) {
        let Some(bs) = at.seen.sample(sampler.next_2d()) else { return };
        let wi = at.frame.to_world(bs.wi);
        // The weight needs p_b as a function of the direction, the same function the light
        // technique's weight used (`eval_pdf`), so the two weights of a direction sum to one
        // exactly. (`bs.pdf`, from the sampled half vector, can differ from it by rounding at
        // grazing near-mirror angles; the sample's f / p_b, `bs.weight`, uses the exact one.)
        let pdf = || at.seen.pdf(bs.wi);
        // The light technique's pdf of the direction to y on `light`: p_l = P(light) p_w(wi | light).
        let light_pdf = |light, y: &Hit| {
            self.lights.pmf(&at.selection, light) * self.lights.pdf(light, &at.point, &y.point)
        };
        if !at.every_emitter {
            let Some((y, light, radiance)) = self.scene.emitter_hit_from::<true>(from_x, wi, at.x.object)
            else {
                return;
            };
            // (A light in closed form here is then unblocked: its f (V - 1) is zero.)
            if radiance == Rgb::ZERO || at.analytic(light) {
                return;
            }
            let (pdf, pdf_other) = (pdf(), light_pdf(light, &y));
            found(Found { value: bs.weight * radiance, pdf, pdf_other, delta: false });
            return;
        }
        let pdf = pdf();
        self.scene.emitters_along_from(from_x, wi, at.x.object, |y, light, radiance, visible| {
            let value = match (at.analytic(light), visible) {
                (false, true) => bs.weight * radiance,
                (true, false) => -(bs.weight * radiance),
                (false, false) | (true, true) => return,
            };
            if radiance != Rgb::ZERO {
                found(Found { value, pdf, pdf_other: light_pdf(light, &y), delta: false });
            }
        });
    }
}

/// Adds a light sample's weighted contribution w_l f / (m_l p_l), with the weight on
/// q_l = m_l p_l and q_b = m_b p_b (m: sample counts, or technique probabilities in the one-sample
/// model). A delta light cannot be hit by a BSDF sample: its weight is one.
#[inline]
fn add_light_sample(to: &mut TechniqueEstimate, method: Method, s: &Found, m_light: f32, m_bsdf: f32) {
    let w =
        if s.delta { 1.0 } else { method.weight(Technique::Light, m_light * s.pdf, m_bsdf * s.pdf_other) };
    to.add(s.value * (w / (m_light * s.pdf)), w);
}

/// Adds a BSDF sample's weighted contribution w_b f / (m_b p_b) (`value` is already f / p_b),
/// with the weight on q_l = m_l p_l and q_b = m_b p_b.
#[inline]
fn add_bsdf_sample(to: &mut TechniqueEstimate, method: Method, s: &Found, m_light: f32, m_bsdf: f32) {
    let w = method.weight(Technique::Bsdf, m_light * s.pdf_other, m_bsdf * s.pdf);
    to.add(s.value * (w / m_bsdf), w);
}

/// The shading point `x` (on a surface of non-black material `bsdf`) seen from `wo`, for the
/// integrator `it`: the one body of [`Integrator::shading`] and, on the microcontrollers, of
/// [`Integrator::estimate_direct`]'s own (a macro, not a function both call: see there).
macro_rules! shading {
    ($it:expr, $x:expr, $bsdf:expr, $wo:expr) => {{
        let (it, x, bsdf, wo): (&Integrator<'_, St, S, L, M>, &Hit, &Material, Vec3) = ($it, $x, $bsdf, $wo);
        let frame = Frame::from_normal(x.point.n);
        let point = ShadingPoint { p: x.point.p, n: x.point.n, wo, bsdf: *bsdf };
        let wo = bsdf.to_local(&frame, wo);
        let seen = bsdf.seen_from(wo);
        let control_variate = St::ControlVariate::ON && matches!(bsdf, Material::Lambertian { .. });
        let covered = if control_variate {
            let cover = if St::ControlVariate::AUTO { it.auto_cover } else { Cover::Every };
            closed_form::unoccluded_light::<
                <St::Lights as LightStrategies<L>>::Spheres,
                <St::Lights as LightStrategies<L>>::Quads,
                St::ControlVariate,
                S,
                L,
                M,
            >(it.scene, bsdf, x, wo.z, cover)
        } else {
            Covered::default()
        };
        // The `auto` control variate's unblocked lights are exact: they need no samples, and where
        // every light is exact none is drawn. Where a covered light may be blocked, the BSDF
        // samples look for the emitters behind the first surface (their f (V - 1)).
        let exact = if St::ControlVariate::AUTO { covered.exact } else { 0 };
        let residual = Residual { exact };
        let n = it.scene.lights().len();
        let all_exact = St::ControlVariate::AUTO && n > 0 && n <= 64 && exact == u64::MAX >> (64 - n);
        let every_emitter = control_variate && (!St::ControlVariate::AUTO || covered.lights & !exact != 0);
        // On the microcontrollers the selection that depends on the point reads a copy of it:
        // lent to the out-of-line selection, `point` itself would be built apart and copied into
        // the struct after, at every shading point. The other selections take no copy, nor does
        // x86, where it would cost.
        let selection = if cfg!(target_os = "none")
            && <<St::Lights as LightStrategies<L>>::Selection as Select<L>>::LOCAL
        {
            let copy = point;
            it.lights.selection_in(&copy, &frame, &seen, residual)
        } else {
            it.lights.selection_in(&point, &frame, &seen, residual)
        };
        let (covered, unoccluded) = (covered.lights, covered.radiance);
        Shading {
            x,
            bsdf,
            frame,
            seen,
            point,
            selection,
            control_variate,
            covered,
            unoccluded,
            all_exact,
            every_emitter,
        }
    }};
}
use shading;

/// A shading point as the techniques see it: the BSDF seen from `wo` in the local frame, and
/// the light selection there (`L`: the scene's light capacity).
pub struct Shading<'a, St: Strategies<L>, const L: usize> {
    x: &'a Hit,
    bsdf: &'a Material,
    frame: Frame,
    /// The BSDF seen from `wo` in the local frame: what f cos and the pdf need of `wo` alone,
    /// computed once for the light and BSDF samples.
    seen: Outgoing,
    /// The shading point as the light sampler sees it (world `wo`).
    point: ShadingPoint,
    /// Light selection here, shared by light samples and the BSDF samples' weights.
    selection: SelectionAt<St::Lights, L>,
    /// The control variate applies here (it is on and the receiver is Lambertian).
    control_variate: bool,
    /// Bit i: light i's unoccluded part is in closed form here.
    covered: u64,
    /// The closed-form reflected radiance of those lights.
    unoccluded: Rgb,
    /// Every light's part is exact here (the `auto` control variate covers them all and nothing
    /// can block them): no sample is drawn.
    all_exact: bool,
    /// The BSDF samples look for every emitter along their rays (the f (V - 1) of covered lights
    /// that may be blocked).
    every_emitter: bool,
}

impl<St: Strategies<L>, const L: usize> Shading<'_, St, L> {
    /// `f` of the shadow and BSDF rays from here, with the origin terms their queries need: with
    /// the control variate, whose BSDF rays look for every emitter along them, those of all
    /// objects; else those of the objects the culled queries may test. (Where the rays keep no
    /// origin terms, that is one case.)
    #[inline(always)]
    fn with_rays<const S: usize, const M: usize, R>(
        &self,
        scene: &Scene<S, L, M>,
        f: impl FnOnce(&PointRays<S>) -> R,
    ) -> R {
        let among =
            if self.every_emitter || !POINT_TERMS { u32::MAX } else { scene.reachable(self.x.object) };
        scene.with_rays_among(self.x.point.p, among, f)
    }

    /// Whether light `light`'s part is sampled as f (V - 1) (its unoccluded part is in closed form).
    #[inline]
    fn analytic(&self, light: LightId) -> bool {
        let i = light.index();
        // (`covered` is 0 without the control variate: skip the 64-bit shift then.)
        self.control_variate && i < 64 && self.covered & (1 << i) != 0
    }
}

/// The material of the surface `x` hit, if it reflects anything.
#[inline]
fn reflecting<'a, const S: usize, const L: usize, const M: usize>(
    scene: &'a Scene<S, L, M>,
    x: &Hit,
) -> Option<&'a Material> {
    scene.material(x.object).filter(|m| !m.is_black())
}

/// A sample that found light: its integrand value (not divided by any pdf for light samples;
/// divided by the BSDF pdf for BSDF samples), its own technique's pdf and the other's.
struct Found {
    value: Rgb,
    pdf: f32,
    pdf_other: f32,
    delta: bool,
}
