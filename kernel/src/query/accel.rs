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
mod packets {
    use heapless::Vec;
    use wide::{CmpGe, CmpGt, CmpLe, CmpLt, CmpNe, f32x4};

    use super::{Filter, RaysFrom, Target};
    use crate::geometry::Shape;
    use crate::num::Vec3;

    const LANES: usize = 4;
    /// Object index of an empty lane.
    const EMPTY: u16 = u16::MAX;

    #[derive(Clone, Copy, Debug, PartialEq)]
    struct SpherePacket {
        c: [f32x4; 3],
        r2: f32x4,
        lanes: Lanes,
    }

    #[derive(Clone, Copy, Debug, PartialEq)]
    struct QuadPacket {
        n: [f32x4; 3],
        plane: f32x4,
        p0: [f32x4; 3],
        s_axis: [f32x4; 3],
        t_axis: [f32x4; 3],
        lanes: Lanes,
    }

    /// The objects in a packet's lanes.
    #[derive(Clone, Copy, Debug, PartialEq)]
    struct Lanes {
        object: [u16; LANES],
        emitter: [bool; LANES],
        /// Some lane holds an emitter; some lane holds another object. A query that looks at
        /// neither skips the packet.
        emitters: bool,
        others: bool,
        /// Bit i for each lane's object i below
        /// [`CULLED`](crate::query::camera_cull::CULLED); `beyond`: some lane's object is
        /// not below it. A query [`Filter::Among`] objects none of which are here skips the
        /// packet.
        bits: u32,
        beyond: bool,
    }

    impl Lanes {
        const EMPTY: Self = Self {
            object: [EMPTY; LANES],
            emitter: [false; LANES],
            emitters: false,
            others: false,
            bits: 0,
            beyond: false,
        };

        /// Lane `k` holds object `id`, not (yet) an emitter.
        fn set(&mut self, k: usize, id: u16) {
            if let Some(o) = self.object.get_mut(k) {
                *o = id;
                self.others = true;
                match crate::query::camera_cull::object_bit(usize::from(id)) {
                    Some(bit) => self.bits |= bit,
                    None => self.beyond = true,
                }
            }
        }

        /// Whether a query with `filter` may look at some object here: not when it looks
        /// [`Filter::Among`] objects none of which are in the packet, nor (see
        /// [`Filter::may_admit`]) at a role none of them has.
        #[inline(always)]
        fn looked_at(&self, filter: Filter) -> bool {
            let among = match filter {
                Filter::Among(m) => self.beyond || m & self.bits != 0,
                _ => true,
            };
            among && filter.may_admit(self.emitters, self.others)
        }

        /// Marks object `object` as an emitter, if it is here.
        fn set_emitter(&mut self, object: usize) {
            for (o, e) in self.object.iter().zip(self.emitter.iter_mut()) {
                *e |= usize::from(*o) == object;
            }
            let lanes = || self.object.iter().zip(&self.emitter).filter(|(o, _)| **o != EMPTY);
            self.emitters = lanes().any(|(_, e)| *e);
            self.others = lanes().any(|(_, e)| !*e);
        }

        /// Whether the object in lane `k` (< 4) is one `filter` admits.
        #[inline(always)]
        fn admitted(&self, filter: Filter, k: usize) -> bool {
            filter.admits(self.object[k], self.emitter[k])
        }

        /// The object in lane `k` (< 4).
        #[inline(always)]
        fn object(&self, k: usize) -> usize {
            usize::from(self.object[k])
        }
    }

    /// Sets lane `k` of the three vectors `v` to the components of `x`.
    fn set3(v: &mut [f32x4; 3], k: usize, x: Vec3) {
        for (lanes, c) in v.iter_mut().zip([x.x, x.y, x.z]) {
            set(lanes, k, c);
        }
    }

    fn set(v: &mut f32x4, k: usize, x: f32) {
        let mut a = v.to_array();
        if let Some(slot) = a.get_mut(k) {
            *slot = x;
        }
        *v = f32x4::from(a);
    }

    /// `a . b` per lane, as `Vec3::dot` computes it: (x x' + y y') + z z'.
    #[inline(always)]
    fn dot(a: &[f32x4; 3], b: &[f32x4; 3]) -> f32x4 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    /// The ray's origin and direction in every lane.
    struct RayLanes {
        o: [f32x4; 3],
        d: [f32x4; 3],
    }

    impl RayLanes {
        #[inline(always)]
        fn new(o: Vec3, d: Vec3) -> Self {
            Self {
                o: [f32x4::splat(o.x), f32x4::splat(o.y), f32x4::splat(o.z)],
                d: [f32x4::splat(d.x), f32x4::splat(d.y), f32x4::splat(d.z)],
            }
        }
    }

    impl SpherePacket {
        const EMPTY: Self = Self { c: [f32x4::ZERO; 3], r2: f32x4::new([-1.0; LANES]), lanes: Lanes::EMPTY };

        /// Bit k set: the line of the ray may meet lane k's sphere (the discriminant of
        /// `Shape::intersect` is not negative, NaN included, as there).
        #[inline(always)]
        fn candidates(&self, r: &RayLanes) -> i32 {
            let f = [r.o[0] - self.c[0], r.o[1] - self.c[1], r.o[2] - self.c[2]];
            let b = dot(&f, &r.d);
            let l = [f[0] - r.d[0] * b, f[1] - r.d[1] * b, f[2] - r.d[2] * b];
            let disc = self.r2 - dot(&l, &l);
            !disc.cmp_lt(f32x4::ZERO).move_mask() & 0xf
        }
    }

    impl QuadPacket {
        const EMPTY: Self = Self {
            n: [f32x4::ZERO; 3],
            plane: f32x4::new([f32::NAN; LANES]),
            p0: [f32x4::ZERO; 3],
            s_axis: [f32x4::ZERO; 3],
            t_axis: [f32x4::ZERO; 3],
            lanes: Lanes::EMPTY,
        };

        /// Each lane's hit distance as `Shape::intersect` computes it, and a bit mask of the lanes
        /// hit in `(t_min, t_max)`.
        #[inline(always)]
        fn distances(&self, r: &RayLanes, t_min: f32, t_max: f32) -> ([f32; LANES], i32) {
            let denom = dot(&self.n, &r.d);
            let t = (self.plane - dot(&self.n, &r.o)) / denom;
            let q = [
                (r.o[0] + r.d[0] * t) - self.p0[0],
                (r.o[1] + r.d[1] * t) - self.p0[1],
                (r.o[2] + r.d[2] * t) - self.p0[2],
            ];
            let s = dot(&q, &self.s_axis);
            let v = dot(&q, &self.t_axis);
            let (zero, one) = (f32x4::ZERO, f32x4::ONE);
            let hit = t.cmp_gt(f32x4::splat(t_min))
                & t.cmp_lt(f32x4::splat(t_max))
                & denom.cmp_ne(zero)
                & s.cmp_ge(zero)
                & s.cmp_le(one)
                & v.cmp_ge(zero)
                & v.cmp_le(one);
            (t.to_array(), hit.move_mask())
        }
    }

    /// The lanes whose bit is set in `mask`, in increasing order.
    #[inline(always)]
    fn lanes(mask: i32) -> impl Iterator<Item = usize> {
        let mut m = mask as u32;
        core::iter::from_fn(move || {
            (m != 0).then(|| {
                let k = m.trailing_zeros() as usize;
                m &= m - 1;
                k
            })
        })
    }

    /// The scene's shapes in packets of four (see the module docs). At most `S` packets of each
    /// kind.
    #[derive(Clone, Debug)]
    pub struct Packets<const S: usize> {
        spheres: Vec<SpherePacket, S>,
        quads: Vec<QuadPacket, S>,
        sphere_count: usize,
        quad_count: usize,
    }

    impl<const S: usize> Default for Packets<S> {
        fn default() -> Self {
            Self::EMPTY
        }
    }

    impl<const S: usize> Packets<S> {
        /// No shapes.
        pub const EMPTY: Self =
            Self { spheres: Vec::new(), quads: Vec::new(), sphere_count: 0, quad_count: 0 };
    }

    impl<const S: usize> Packets<S> {
        /// Adds object `object` (there is room: the scene holds at most `S` objects).
        pub fn push(&mut self, object: usize, shape: &Shape) {
            let Ok(id) = u16::try_from(object) else { return };
            let k = match shape {
                Shape::Sphere(_) => self.sphere_count % LANES,
                Shape::Quad(_) => self.quad_count % LANES,
            };
            match shape {
                Shape::Sphere(_) => {
                    let Some((c, r)) = shape.as_sphere() else { return };
                    if k == 0 && self.spheres.push(SpherePacket::EMPTY).is_err() {
                        return;
                    }
                    let Some(p) = self.spheres.last_mut() else { return };
                    set3(&mut p.c, k, c);
                    set(&mut p.r2, k, r * r);
                    p.lanes.set(k, id);
                    self.sphere_count += 1;
                }
                Shape::Quad(q) => {
                    if k == 0 && self.quads.push(QuadPacket::EMPTY).is_err() {
                        return;
                    }
                    let Some(p) = self.quads.last_mut() else { return };
                    let (n, plane, p0, s_axis, t_axis) = q.parts();
                    set3(&mut p.n, k, n);
                    set3(&mut p.p0, k, p0);
                    set3(&mut p.s_axis, k, s_axis);
                    set3(&mut p.t_axis, k, t_axis);
                    set(&mut p.plane, k, plane);
                    p.lanes.set(k, id);
                    self.quad_count += 1;
                }
            }
        }

        /// Marks object `object` as an emitter.
        pub fn set_emitter(&mut self, object: usize) {
            for p in self.spheres.iter_mut() {
                p.lanes.set_emitter(object);
            }
            for p in self.quads.iter_mut() {
                p.lanes.set_emitter(object);
            }
        }

        /// The nearest hit in `(t_min, t_max)` along the ray from `from` in direction `dir`
        /// among the objects `filter` admits, as `(distance, object)`; `objects` are the
        /// scene's objects. `None` when nothing is hit.
        #[inline(always)]
        pub(crate) fn nearest<const N: usize, const K: bool>(
            &self,
            from: &RaysFrom<N, K>,
            dir: Vec3,
            t_min: f32,
            t_max: f32,
            filter: Filter,
            objects: &[impl Target],
        ) -> Option<(f32, usize)> {
            let shape = |i: usize| objects.get(i).map(Target::shape);
            let (mut t_far, mut best) = (t_max, usize::MAX);
            let mut offer = |t: f32, i: usize| {
                // A front-to-back loop keeps the first of equal distances: the lowest index.
                if t < t_far || (t == t_far && best != usize::MAX && i < best) {
                    (t_far, best) = (t, i);
                }
            };
            let r = RayLanes::new(from.origin, dir);
            let looked_at = |l: &Lanes| l.looked_at(filter);
            for p in &self.quads {
                if !looked_at(&p.lanes) {
                    continue;
                }
                let (t, hits) = p.distances(&r, t_min, t_max);
                for k in lanes(hits) {
                    if p.lanes.admitted(filter, k) {
                        offer(t[k], p.lanes.object(k));
                    }
                }
            }
            for p in &self.spheres {
                if !looked_at(&p.lanes) {
                    continue;
                }
                for k in lanes(p.candidates(&r)) {
                    if p.lanes.admitted(filter, k) {
                        let i = p.lanes.object(k);
                        if let Some(t) = shape(i).and_then(|s| s.intersect(&from.ray(dir), t_min, t_max)) {
                            offer(t, i);
                        }
                    }
                }
            }
            (best != usize::MAX).then_some((t_far, best))
        }

        /// True when any object `filter` admits is hit in `(t_min, t_max)` along the ray from
        /// `from` in direction `dir`; `objects` are the scene's objects.
        #[inline(always)]
        pub(crate) fn any<const N: usize, const K: bool>(
            &self,
            from: &RaysFrom<N, K>,
            dir: Vec3,
            t_min: f32,
            t_max: f32,
            filter: Filter,
            objects: &[impl Target],
        ) -> bool {
            let shape = |i: usize| objects.get(i).map(Target::shape);
            let r = RayLanes::new(from.origin, dir);
            let looked_at = |l: &Lanes| l.looked_at(filter);
            for p in self.quads.iter().filter(|p| looked_at(&p.lanes)) {
                let (_, hits) = p.distances(&r, t_min, t_max);
                if lanes(hits).any(|k| p.lanes.admitted(filter, k)) {
                    return true;
                }
            }
            for p in self.spheres.iter().filter(|p| looked_at(&p.lanes)) {
                for k in lanes(p.candidates(&r)) {
                    if p.lanes.admitted(filter, k)
                        && shape(p.lanes.object(k))
                            .and_then(|s| s.intersect(&from.ray(dir), t_min, t_max))
                            .is_some()
                    {
                        return true;
                    }
                }
            }
            false
        }
    }
}

/// Microcontrollers keep no packets (no vector unit, and RAM for one copy of the shapes only):
/// the queries run a plain loop over the objects, in index order, through the rays' origin terms
/// where they are kept.
#[cfg(any(target_os = "none", test))]
mod plain {
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
            Query { ray: from.ray(dir), t_min, t_max, span }
                .run::<true, S, K>(from, filter, objects)
                .is_some()
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
                _ => {
                    self.scan::<RUNTIME, RUNTIME, S, KEPT, true, true>(from, skip, among, roles, ANY, objects)
                }
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
}

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
