//! Microcontrollers keep no packets (no vector unit, and RAM for one copy of the shapes only):
//! the queries run a plain loop over the objects, in index order, through the rays' origin terms
//! where they are kept.

use super::{Filter, RaysFrom, Target, among_holds};
use crate::geometry::{FixedDir, Ray, Shape};
use crate::num::{SOFT_FLOAT, Vec3};
use crate::query::camera_cull::CULLED;

/// No packets: the span of object indices that holds the emitters (a query for emitters
/// looks there only).
#[derive(Clone, Debug, Default)]
pub struct Packets<const S: usize> {
    emitters: core::ops::Range<usize>,
}

impl<const S: usize> Packets<S> {
    /// No shapes.
    #[cfg_attr(not(target_os = "none"), allow(dead_code))]
    pub const EMPTY: Self = Self { emitters: 0..0 };

    /// Nothing to store.
    pub fn push(&mut self, _object: usize, _shape: &Shape) {}

    /// Marks object `object` as an emitter.
    pub fn set_emitter(&mut self, object: usize) {
        let e = &self.emitters;
        self.emitters =
            if e.is_empty() { object..object + 1 } else { e.start.min(object)..e.end.max(object + 1) };
    }

    /// The objects a query with `filter` looks at, among `n`.
    #[inline]
    fn span(&self, filter: Filter, n: usize) -> core::ops::Range<usize> {
        match filter {
            Filter::EmittersBut(_) => self.emitters.clone(),
            _ => 0..n,
        }
    }

    /// The nearest hit in `(t_min, t_max)` along the ray from `from` in direction `dir`
    /// among the objects `filter` admits, as `(distance, object)`; `objects` are the
    /// scene's objects. `None` when nothing is hit.
    #[inline]
    pub(crate) fn nearest<const K: bool>(
        &self,
        from: &RaysFrom<S, K>,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
        filter: Filter,
        objects: &[impl Target],
    ) -> Option<(f32, usize)> {
        let span = self.span(filter, objects.len());
        // Sliced here, where the filter is known: the whole slice costs no check.
        let objects = objects.get(span.clone()).unwrap_or_default();
        Query { ray: from.ray(dir), t_min, t_max, span }.run::<false, S, K>(from, filter, objects)
    }

    /// True when any object `filter` admits is hit in `(t_min, t_max)` along the ray from
    /// `from` in direction `dir`; `objects` are the scene's objects.
    #[inline(always)]
    pub(crate) fn any<const K: bool>(
        &self,
        from: &RaysFrom<S, K>,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
        filter: Filter,
        objects: &[impl Target],
    ) -> bool {
        let span = self.span(filter, objects.len());
        let objects = objects.get(span.clone()).unwrap_or_default();
        Query { ray: from.ray(dir), t_min, t_max, span }.run::<true, S, K>(from, filter, objects).is_some()
    }
}

/// The roles of object a query looks at: all, emitters only, non-emitters only.
const ALL: u8 = 0;
const EMITTERS: u8 = 1;
const OTHERS: u8 = 2;
/// A parameter of [`Query::scan`] decided at run time.
const RUNTIME: u8 = 3;

/// A ray, its distance range and the span of objects to look at (the objects a query runs
/// on are that span of the scene's).
struct Query {
    ray: Ray,
    t_min: f32,
    t_max: f32,
    span: core::ops::Range<usize>,
}

impl Query {
    /// The query with `filter`, nearest hit or with `ANY` any hit. The queries of a camera
    /// sample on a target with an FPU get a copy of the loop each, with the filter built
    /// in: the camera ray's nearest hit among its tile's candidates, the BSDF ray's nearest
    /// emitter, and the any hit among a mask's occluders that the shadow ray and the BSDF
    /// ray's occlusion test share; the rest share one. (Where f32 operations are soft-float
    /// calls, the loop's own instructions hardly count: one copy for all.)
    #[inline]
    fn run<const ANY: bool, const S: usize, const KEPT: bool>(
        &self,
        from: &RaysFrom<S, KEPT>,
        filter: Filter,
        objects: &[impl Target],
    ) -> Option<(f32, usize)> {
        // One object to skip is given twice: the loop's two tests are then one.
        const NONE: (usize, usize) = (usize::MAX, usize::MAX);
        let (roles, skip, among) = match filter {
            Filter::AllBut(a) => (ALL, (a, a), u32::MAX),
            Filter::AllButTwo(a, b) => (ALL, (a, b), u32::MAX),
            Filter::EmittersBut(a) => (EMITTERS, (a, a), u32::MAX),
            Filter::OthersBut(a) => (OTHERS, (a, a), u32::MAX),
            Filter::Among(m) => (ALL, NONE, m),
        };
        // The camera's and the shadow rays' queries skip nothing but the objects they cannot
        // hit: their copies of the loop test `among` and no skip, the others `skip` and no
        // `among`.
        let culls = matches!(filter, Filter::Among(_));
        match (SOFT_FLOAT, ANY, roles, KEPT, culls) {
            (false, false, ALL, true, true) => {
                self.scan::<0, ALL, S, KEPT, false, true>(from, skip, among, roles, ANY, objects)
            }
            (false, true, ALL, false, true) => {
                self.scan::<1, ALL, S, KEPT, false, true>(from, skip, among, roles, ANY, objects)
            }
            (false, false, EMITTERS, false, false) => {
                self.scan::<0, EMITTERS, S, KEPT, true, false>(from, skip, among, roles, ANY, objects)
            }
            _ => self.scan::<RUNTIME, RUNTIME, S, KEPT, true, true>(from, skip, among, roles, ANY, objects),
        }
    }

    /// The loop of the queries: front to back, skipping objects `skip`, those not `among`
    /// ([`Filter::Among`]) and those whose role `roles` leaves out, each test bounded by the
    /// nearest hit so far; with `any`, the first hit found. With `KEPT`, through the kept
    /// terms. `ANY_` (0, 1) and `ROLES_` fix `any` and `roles` in this copy of the loop,
    /// unless they are [`RUNTIME`]; without `SKIPS`, `skip` must be none (`usize::MAX`
    /// twice), and without `CULLS`, `among` every object: the loop does not test them.
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn scan<
        const ANY_: u8,
        const ROLES_: u8,
        const S: usize,
        const KEPT: bool,
        const SKIPS: bool,
        const CULLS: bool,
    >(
        &self,
        from: &RaysFrom<S, KEPT>,
        skip: (usize, usize),
        among: u32,
        roles: u8,
        any: bool,
        objects: &[impl Target],
    ) -> Option<(f32, usize)> {
        let roles = if ROLES_ == RUNTIME { roles } else { ROLES_ };
        let any = if ANY_ == RUNTIME { any } else { ANY_ == 1 };
        let admits = |i: usize, o: &_| {
            (!SKIPS || (i != skip.0 && i != skip.1))
                && (!CULLS || among_holds(among, i))
                && (roles == ALL || (roles == EMITTERS) == Target::emits(o))
        };
        let (ray, t_min) = (&self.ray, self.t_min);
        let (mut t_far, mut best) = (self.t_max, None);
        let first = self.span.start;
        if CULLS && !SKIPS && ROLES_ == ALL && ANY_ != RUNTIME {
            // The camera's and the shadow rays' copies on a target with an FPU: straight to
            // the candidates, in increasing index order like the loops below (set bits,
            // then the objects from CULLED on).
            let dir = FixedDir::new(ray.dir);
            let terms = from.terms().get(self.span.clone()).unwrap_or_default();
            let (mut bits, mut beyond) = (if first == 0 { among } else { u32::MAX }, CULLED);
            loop {
                let i = if bits != 0 {
                    let i = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    i
                } else if beyond < objects.len() {
                    beyond += 1;
                    beyond - 1
                } else {
                    break;
                };
                let Some(o) = objects.get(i) else { continue };
                let t = if KEPT {
                    let Some(terms) = terms.get(i) else { continue };
                    o.shape().intersect_from(terms, ray, &dir, t_min, t_far)
                } else {
                    o.shape().intersect_inlined(ray, t_min, t_far)
                };
                if let Some(t) = t {
                    (t_far, best) = (t, Some(first + i));
                    if any {
                        break;
                    }
                }
            }
        } else if KEPT {
            let dir = FixedDir::new(ray.dir);
            let terms = from.terms().get(self.span.clone()).unwrap_or_default();
            for (i, (o, terms)) in (first..).zip(objects.iter().zip(terms)) {
                if admits(i, o) {
                    if let Some(t) = o.shape().intersect_from(terms, ray, &dir, t_min, t_far) {
                        (t_far, best) = (t, Some(i));
                        if any {
                            break;
                        }
                    }
                }
            }
        } else {
            for (i, o) in (first..).zip(objects) {
                if admits(i, o) {
                    if let Some(t) = o.shape().intersect_inlined(ray, t_min, t_far) {
                        (t_far, best) = (t, Some(i));
                        if any {
                            break;
                        }
                    }
                }
            }
        }
        best.map(|i| (t_far, i))
    }
}
