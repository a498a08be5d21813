//! Lights in proportion to their estimated contribution at the shading point.

use crate::light::sample::{LightChoice, ShadingPoint};
use crate::light::select::importance::{LightGeometry, LightTable, Receiver, weighs_bsdf};
use crate::light::select::{LightSelection, Residual, Select, Uniform, choice};
use crate::num::Frame;
use crate::sampling::GridDistribution;
use crate::scene::{LightId, Outgoing, Scene};

/// The share of the BSDF-free importance in light selection by contribution: every light that
/// can send light to the shading point is chosen with at least this share of its importance's
/// probability, even where the BSDF toward its centre is zero (a near-mirror GGX lobe that
/// misses the centre of a light whose edge it sees).
pub const CONTRIBUTION_FLOOR: f32 = 0.1;

/// Proportional to each light's estimated contribution at the shading point, BSDF included
/// ([`LightCone::contribution`](crate::light::select::importance::LightCone::contribution)),
/// mixed with a share [`CONTRIBUTION_FLOOR`] of its BSDF-free importance
/// ([`LightCone::importance`](crate::light::select::importance::LightCone::importance)) so that
/// every light that can contribute keeps a non-zero probability (on Lambertian receivers, by the
/// importance alone); on the grid of the random number like [`ByPower`](crate::light::select::ByPower).
/// A scene's only light is chosen with probability one (uniformly); a light that certainly sends
/// nothing to the point is never chosen. Costs O(lights) per shading point.
#[derive(Clone, Debug)]
pub struct ByContribution<const L: usize> {
    /// Each light's terms of its cone seen from a point.
    lights: LightTable<L>,
    /// Among fewer than two lights.
    uniform: Uniform,
    /// Whether the choice depends on the point: among two lights or more.
    local: bool,
}

impl<const L: usize> Select<L> for ByContribution<L> {
    const KIND: LightSelection = LightSelection::Contribution;
    const LOCAL: bool = true;
    /// The lights' probabilities here; empty among fewer than two lights, and where no light can
    /// contribute.
    type At = GridDistribution<L>;

    fn new<const S: usize, const M: usize>(scene: &Scene<S, L, M>) -> Self {
        let mut lights = LightTable::default();
        for light in scene.lights() {
            // At most L lights: every push fits.
            let _ = lights.push(LightGeometry::new(light, scene.light_shape(light)));
        }
        let n = scene.lights().len();
        ByContribution { lights, uniform: Uniform::among(n), local: n > 1 }
    }

    #[inline]
    fn at(
        &self,
        point: &ShadingPoint,
        frame: &Frame,
        seen: &Outgoing,
        residual: Residual,
    ) -> GridDistribution<L> {
        if !self.local {
            return GridDistribution::default();
        }
        self.weights(point, frame, seen, residual)
    }

    #[inline]
    fn select(&self, at: &GridDistribution<L>, bits: u32) -> Option<(LightChoice, f32)> {
        if !self.local {
            return <Uniform as Select<L>>::select(&self.uniform, &(), bits);
        }
        at.sample_reusing(bits).map(choice)
    }

    #[inline]
    fn pmf(&self, at: &GridDistribution<L>, light: LightId) -> f32 {
        if !self.local {
            return <Uniform as Select<L>>::pmf(&self.uniform, &(), light);
        }
        at.pmf(light.index())
    }
}

/// The sum of the finite, non-negative weights `w`, made finite: where it overflows (lights near
/// the 1e20 emission cap seen from close by), every weight is first divided by the largest, in
/// place (the distribution they give is the same), a positive one to at least
/// [`f32::MIN_POSITIVE`] (below 1e-45 of the largest, it would round to none), so that no
/// light's share, nor the floor share of the mixture, rounds to zero against an infinite sum.
#[inline]
fn finite_sum(w: &mut [f32]) -> f32 {
    let sum = w.iter().sum::<f32>();
    if sum.is_finite() {
        return sum;
    }
    let largest = w.iter().fold(0.0f32, |m, &v| if v > m { v } else { m });
    if !(largest > 0.0 && largest.is_finite()) {
        return sum;
    }
    w.iter_mut().filter(|v| **v > 0.0).for_each(|v| *v = (*v / largest).max(f32::MIN_POSITIVE));
    w.iter().sum::<f32>()
}

impl<const L: usize> ByContribution<L> {
    /// The mixture of the lights' contributions and importances at `point`. Out of line: the
    /// code around it stays small.
    #[inline(never)]
    fn weights(
        &self,
        point: &ShadingPoint,
        frame: &Frame,
        seen: &Outgoing,
        residual: Residual,
    ) -> GridDistribution<L> {
        let n = self.lights.geometry().len().min(L);
        // The BSDF's part, if it has one: in the receiver's frame.
        let receiver = weighs_bsdf(&point.bsdf).then(|| Receiver::new(seen, frame));
        let (mut importance, mut contribution) = ([0.0f32; L], [0.0f32; L]);
        self.lights.weights(point.p, point.n, receiver.as_ref(), |k, i, c| {
            if let (Some(slot), Some(slot_c)) = (importance.get_mut(k), contribution.get_mut(k)) {
                *slot = i;
                *slot_c = c;
            }
        });
        let importance = &mut importance[..n];
        let contribution = &mut contribution[..n];
        // Lights whose part is exact here need no samples.
        if residual.exact != 0 {
            for (k, (i, c)) in importance.iter_mut().zip(contribution.iter_mut()).enumerate().take(64) {
                if residual.exact & (1 << k) != 0 {
                    (*i, *c) = (0.0, 0.0);
                }
            }
        }
        if receiver.is_some() {
            // The mixture (1 - floor) c_k / sum c + floor i_k / sum i, each part where it has a sum
            // (a finite one: see `finite_sum`).
            let (total_i, total_c) = (finite_sum(importance), finite_sum(contribution));
            let (scale_i, scale_c) = match (total_i > 0.0, total_c > 0.0) {
                (true, true) => (CONTRIBUTION_FLOOR / total_i, (1.0 - CONTRIBUTION_FLOOR) / total_c),
                (false, true) => (0.0, 1.0),
                (_, false) => (1.0, 0.0),
            };
            for (i, c) in importance.iter_mut().zip(contribution.iter()) {
                let mixed = *i * scale_i + *c * scale_c;
                // A light with a weight keeps a share where its part of the mixture falls below
                // f32's normal range, or to none (a weight under 1e-37 of its sum: beside lights
                // at the emission cap). The same grid values either way: any positive weight
                // gets at least one.
                *i = if mixed < f32::MIN_POSITIVE && (*i > 0.0 || *c > 0.0) {
                    f32::MIN_POSITIVE
                } else {
                    mixed
                };
            }
        } else {
            finite_sum(importance);
        }
        GridDistribution::new(importance)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Film, test_desc};
    use crate::num::{Rgb, Vec3};
    use crate::scene::Material;

    /// Two point lights at the emission cap, and a third one far and dim, around a point that
    /// sees them from 1e-12 away: their strengths overflow f32.
    fn scene() -> Scene<1, 3, 1> {
        let mut s: Scene<1, 3, 1> = Scene::new(test_desc(40.0), Film::new(4, 4).unwrap()).unwrap();
        let cap = Rgb::splat(crate::scene::MAX_EMISSION);
        s.add_point_light(Vec3::new(0.0, 1e-12, 0.0), cap).unwrap();
        s.add_point_light(Vec3::new(1e-12, 1e-12, 0.0), cap).unwrap();
        s.add_point_light(Vec3::new(0.0, 10.0, 0.0), Rgb::splat(1.0)).unwrap();
        s
    }

    /// No light that can contribute gets probability zero, nor does the floor share vanish,
    /// when the weights overflow: the lights at the cap share nearly everything, the dim one
    /// keeps a positive share through the floor (GGX receiver) or its importance. (Before: the
    /// lights at the cap had no cone, and the dim one took probability one.)
    #[test]
    fn weights_at_the_emission_cap_keep_every_light() {
        let s = scene();
        let select = <ByContribution<3> as Select<3>>::new(&s);
        for bsdf in
            [Material::lambertian(Rgb::ONE).unwrap(), Material::ggx_conductor(0.01, Rgb::ONE).unwrap()]
        {
            let point = ShadingPoint { p: Vec3::ZERO, n: Vec3::Y, wo: Vec3::Y, bsdf };
            let frame = Frame::from_normal(point.n);
            let seen = bsdf.seen_from(frame.to_local(point.wo));
            let at = select.at(&point, &frame, &seen, Residual::default());
            let p: [f32; 3] = core::array::from_fn(|k| select.pmf(&at, LightId::new(k as u16)));
            assert!(p.iter().all(|&p| p > 0.0), "{bsdf:?}: {p:?}");
            assert!((p.iter().sum::<f32>() - 1.0).abs() < 1e-6, "{p:?}");
            // The lights at the cap share nearly everything.
            assert!(p[0] > 0.01 && p[1] > 0.01 && p[2] < 1e-3, "{p:?}");
            assert!(select.select(&at, 0).is_some());
        }
    }
}
