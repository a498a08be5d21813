//! Ray queries over all of a scene's shapes, four shapes at a time: a structure-of-arrays copy of
//! the shapes in packets of four lanes, whose loops the compiler turns into SIMD instructions.
//!
//! The results are bit for bit those of testing each shape in turn with [`crate::geometry::Shape::intersect`]:
//! - a quad's lane runs the same IEEE operations in the same order as `Shape::intersect`
//!   (add, multiply and divide are exact per lane), so its distance is the same number;
//! - a sphere's lane only decides whether the ray can meet the sphere at all (the discriminant,
//!   computed as `Shape::intersect` does); the few spheres that pass are then intersected by
//!   `Shape::intersect` itself;
//! - the nearest hit is the one a front-to-back loop would keep: the smallest distance, the lowest
//!   object index among equal ones.
//!
//! A packet none of whose objects a query looks at is skipped (the BSDF ray's search for an
//! emitter does not test the quads of a scene whose lights are spheres).
//!
//! Only hosted targets get the packets ([`ENABLED`]); on a microcontroller (no vector unit, and
//! RAM for one copy of the shapes only) the queries run a plain loop over the objects in index
//! order, with the same bits, through the origin terms of the rays (`RaysFrom`) where they
//! are kept (`Shape::intersect_from` and its early rejects).

use heapless::Vec;

use crate::geometry::{OriginTerms, Ray, Shape};
use crate::num::{SOFT_FLOAT, Vec3};
use crate::query::camera_cull::CULLED;

/// Whether scenes keep packets and run ray queries through them on this target.
pub const ENABLED: bool = cfg!(not(target_os = "none"));

/// Rays from one origin, with every object's [`OriginTerms`] when `KEPT`: computed once for all
/// the rays from there instead of once per ray-object test. Microcontrollers keep the camera's
/// ([`CameraRays`]), and a shading point's ([`PointRays`]) where f32 operations are soft-float
/// calls ([`SOFT_FLOAT`]: there, sharing them between the shadow and the BSDF ray pays for the
/// loads and stores; with an FPU the loads and stores cost as much as the terms). The packets
/// of hosted targets keep none.
#[derive(Clone, Debug)]
pub(crate) struct RaysFrom<const S: usize, const KEPT: bool> {
    origin: Vec3,
    /// With `KEPT`, the terms of every object in order (else empty).
    terms: Vec<OriginTerms, S>,
}

/// The rays from the camera.
pub(crate) type CameraRays<const S: usize> = RaysFrom<S, { !ENABLED }>;
/// Whether the rays from a shading point keep origin terms ([`PointRays`]).
pub(crate) const POINT_TERMS: bool = SOFT_FLOAT && !ENABLED;
/// The rays from a shading point (its shadow and BSDF rays).
pub(crate) type PointRays<const S: usize> = RaysFrom<S, POINT_TERMS>;

impl<const S: usize, const KEPT: bool> RaysFrom<S, KEPT> {
    /// The rays from `origin`, before any object is added.
    #[inline]
    pub(crate) const fn new(origin: Vec3) -> Self {
        Self { origin, terms: Vec::new() }
    }

    /// `f` of the rays from `origin` among `shapes` (every object's, in order), built in
    /// place (returning them would copy the terms), with the terms of the objects in `among`
    /// only (bit i for object i below [`CULLED`], and every object from there on): the others
    /// get terms that hit nothing, for queries that do not test them.
    #[inline(always)]
    pub(crate) fn with_among<'a, R>(
        origin: Vec3,
        shapes: impl Iterator<Item = &'a Shape>,
        among: u32,
        f: impl FnOnce(&Self) -> R,
    ) -> R {
        let mut rays = Self::new(origin);
        for (i, shape) in shapes.enumerate() {
            if among_holds(among, i) {
                rays.push(shape);
            } else if KEPT {
                let _ = rays.terms.push(OriginTerms::NONE); // room: at most S objects
            }
        }
        f(&rays)
    }

    /// The same rays with object `shape` added (the scene's next object).
    #[inline]
    pub(crate) fn push(&mut self, shape: &Shape) {
        if KEPT {
            let _ = self.terms.push(shape.origin_terms(self.origin)); // room: at most S objects
        }
    }

    /// The ray from here along the unit direction `dir`.
    #[inline]
    pub(crate) fn ray(&self, dir: Vec3) -> Ray {
        Ray { origin: self.origin, dir }
    }

    /// Whether these are the rays from `origin` (the same bits).
    #[inline]
    pub(crate) fn start_at(&self, origin: Vec3) -> bool {
        let same = |a: f32, b: f32| a.to_bits() == b.to_bits();
        same(self.origin.x, origin.x) && same(self.origin.y, origin.y) && same(self.origin.z, origin.z)
    }

    /// The kept origin terms of every object (with `KEPT`).
    #[cfg_attr(not(target_os = "none"), allow(dead_code))]
    #[inline]
    fn terms(&self) -> &[OriginTerms] {
        &self.terms
    }
}

/// Which objects a query looks at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    /// Every object but one (`usize::MAX`: none).
    AllBut(usize),
    /// Emitters only, but one.
    EmittersBut(usize),
    /// Non-emitters only, but one.
    OthersBut(usize),
    /// Every object but two.
    AllButTwo(usize, usize),
    /// The objects whose bit is set, and every object from [`CULLED`] on (a camera ray's
    /// candidates, [`CameraCull::candidates`](crate::query::camera_cull::CameraCull::candidates)).
    Among(u32),
}

/// Whether the objects `among` holds (see [`Filter::Among`]) include object `i`.
#[inline(always)]
pub(crate) fn among_holds(among: u32, i: usize) -> bool {
    i >= CULLED || among >> (i & (CULLED - 1)) & 1 == 1
}

impl Filter {
    /// Whether the query looks at object `object` (`u16::MAX`: an empty lane), an emitter or not.
    #[cfg_attr(target_os = "none", allow(dead_code))]
    #[inline]
    fn admits(self, object: u16, emitter: bool) -> bool {
        let i = usize::from(object);
        object != u16::MAX
            && match self {
                Filter::AllBut(a) => i != a,
                Filter::EmittersBut(a) => emitter && i != a,
                Filter::OthersBut(a) => !emitter && i != a,
                Filter::AllButTwo(a, b) => i != a && i != b,
                Filter::Among(m) => among_holds(m, i),
            }
    }
}

impl Filter {
    /// Whether the query may look at some object of a (non-empty) group that holds emitters
    /// (`emitters`) and non-emitters (`others`).
    #[cfg_attr(target_os = "none", allow(dead_code))]
    #[inline]
    fn may_admit(self, emitters: bool, others: bool) -> bool {
        match self {
            Filter::EmittersBut(_) => emitters,
            Filter::OthersBut(_) => others,
            Filter::AllBut(_) | Filter::AllButTwo(..) | Filter::Among(_) => true,
        }
    }
}

/// What a ray query needs of an object: its shape and whether it emits.
pub(crate) trait Target {
    /// The object's shape.
    fn shape(&self) -> &Shape;
    /// Whether the object is an emitter.
    #[cfg_attr(not(target_os = "none"), allow(dead_code))]
    fn emits(&self) -> bool;
}

#[cfg(not(target_os = "none"))]
mod packets;

#[cfg(any(target_os = "none", test))]
mod plain;

#[cfg(not(target_os = "none"))]
pub use packets::Packets;
#[cfg(target_os = "none")]
pub use plain::Packets;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Ray, Shape};
    use crate::num::Vec3;
    use crate::sampling::sampler::Sampler;

    impl Target for (Shape, bool) {
        fn shape(&self) -> &Shape {
            &self.0
        }
        fn emits(&self) -> bool {
            self.1
        }
    }

    /// The plain loop the packets must reproduce: nearest hit, front to back.
    fn nearest_loop(
        shapes: &[(Shape, bool)],
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        f: Filter,
    ) -> Option<(f32, usize)> {
        let (mut t_far, mut best) = (t_max, usize::MAX);
        for (i, (s, e)) in shapes.iter().enumerate() {
            if f.admits(i as u16, *e) {
                if let Some(t) = s.intersect(ray, t_min, t_far) {
                    (t_far, best) = (t, i);
                }
            }
        }
        (best != usize::MAX).then_some((t_far, best))
    }

    fn random_shapes(rng: &mut Sampler, n: usize) -> std::vec::Vec<(Shape, bool)> {
        let mut v = std::vec::Vec::new();
        let mut p =
            || Vec3::new(rng.next_f32() * 4.0 - 2.0, rng.next_f32() * 4.0 - 2.0, rng.next_f32() * 4.0 - 2.0);
        for i in 0..n {
            let shape = if i % 3 == 0 {
                Shape::sphere(p(), 0.05 + p().x.abs() * 0.5)
            } else {
                let (p0, e1, e2) = (p(), p() * 0.7, p() * 0.7);
                Shape::quad([p0, p0 + e1, p0 + e1 + e2, p0 + e2])
            };
            if let Ok(s) = shape {
                v.push((s, i % 4 == 1));
            }
        }
        // Two copies of one shape: equal distances, the lower index must win.
        if let Some(&first) = v.first() {
            v.push(first);
        }
        v
    }

    #[test]
    fn packets_give_the_bits_of_the_plain_loop() {
        let mut rng = Sampler::new(3, 1, 4);
        let mut hits = 0;
        for scene in 0..200 {
            // Every tenth scene has more objects than a camera ray's candidate mask holds.
            let shapes = random_shapes(&mut rng, if scene % 10 == 9 { 40 } else { 1 + scene % 13 });
            let mut packets: Packets<48> = Packets::default();
            let mut plain: plain::Packets<48> = plain::Packets::default();
            for (i, (s, e)) in shapes.iter().enumerate() {
                packets.push(i, s);
                plain.push(i, s);
                if *e {
                    packets.set_emitter(i);
                    plain.set_emitter(i);
                }
            }
            for _ in 0..200 {
                let origin = Vec3::new(
                    rng.next_f32() * 8.0 - 4.0,
                    rng.next_f32() * 8.0 - 4.0,
                    rng.next_f32() * 8.0 - 4.0,
                );
                // Half the rays aim near a shape, half go anywhere.
                let jitter = crate::sampling::sample_uniform_sphere(rng.next_2d()) * 0.3;
                let target = shapes[(rng.next_u32() as usize) % shapes.len()].0.centroid() + jitter;
                let dir = if rng.next_f32() < 0.5 {
                    (target - origin).normalize()
                } else {
                    crate::sampling::sample_uniform_sphere(rng.next_2d())
                };
                let ray = Ray { origin, dir };
                let skip = (rng.next_u32() % 20) as usize;
                let t_max = if rng.next_f32() < 0.5 { f32::INFINITY } else { rng.next_f32() * 6.0 };
                let t_min = if rng.next_f32() < 0.8 { 0.0 } else { rng.next_f32() };
                // A camera ray's candidates: a random subset (objects from CULLED on always).
                let among = rng.next_u32() & rng.next_u32();
                for f in [
                    Filter::AllBut(skip),
                    Filter::EmittersBut(skip),
                    Filter::OthersBut(skip),
                    Filter::AllButTwo(skip, 3),
                    Filter::Among(among),
                ] {
                    let want = nearest_loop(&shapes, &ray, t_min, t_max, f);
                    let bits = |h: Option<(f32, usize)>| h.map(|(t, i)| (t.to_bits(), i));
                    let from: RaysFrom<48, false> = RaysFrom::new(ray.origin);
                    let got = packets.nearest(&from, ray.dir, t_min, t_max, f, &shapes);
                    assert_eq!(bits(got), bits(want), "{ray:?} {f:?}");
                    assert_eq!(packets.any(&from, ray.dir, t_min, t_max, f, &shapes), want.is_some());
                    // The microcontrollers' plain loop, with the full tests and through kept terms.
                    let got = plain.nearest(&from, ray.dir, t_min, t_max, f, &shapes);
                    assert_eq!(bits(got), bits(want), "plain: {ray:?} {f:?}");
                    assert_eq!(plain.any(&from, ray.dir, t_min, t_max, f, &shapes), want.is_some());
                    let mut kept: RaysFrom<48, true> = RaysFrom::new(ray.origin);
                    for (s, _) in &shapes {
                        kept.push(s);
                    }
                    let got = plain.nearest(&kept, ray.dir, t_min, t_max, f, &shapes);
                    assert_eq!(bits(got), bits(want), "kept terms: {ray:?} {f:?}");
                    assert_eq!(plain.any(&kept, ray.dir, t_min, t_max, f, &shapes), want.is_some());
                    if let Filter::Among(m) = f {
                        // Terms kept for the objects the query tests only: the same answer.
                        let shapes_only = shapes.iter().map(|(s, _)| s);
                        let got = RaysFrom::<48, true>::with_among(ray.origin, shapes_only, m, |rays| {
                            plain.nearest(rays, ray.dir, t_min, t_max, f, &shapes)
                        });
                        assert_eq!(bits(got), bits(want), "terms among {m:08x}: {ray:?}");
                    }
                    hits += usize::from(want.is_some());
                }
            }
        }
        // The check is not vacuous: many rays hit something.
        assert!(hits > 20_000, "{hits}");
    }

    #[test]
    fn terms_of_no_origin_hit_nothing() {
        let mut rng = Sampler::new(4, 1, 4);
        let shapes = random_shapes(&mut rng, 200);
        let mut hits = 0;
        for (s, _) in &shapes {
            for _ in 0..20 {
                let origin =
                    Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 8.0 - Vec3::splat(4.0);
                let ray = Ray { origin, dir: (s.centroid() - origin).normalize() };
                hits += usize::from(s.intersect(&ray, 0.0, f32::INFINITY).is_some());
                let dir = crate::geometry::FixedDir::new(ray.dir);
                let none = s.intersect_from(&OriginTerms::NONE, &ray, &dir, 0.0, f32::INFINITY);
                assert_eq!(none, None, "{s:?} {ray:?}");
            }
        }
        assert!(hits > 3000, "{hits}");
    }
}
