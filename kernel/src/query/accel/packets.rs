//! Shapes four to a SIMD packet (hosted targets): each query tests four shapes of a kind at
//! once, lane by lane with the operations of the scalar test in the same order (the same bits).

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
    pub const EMPTY: Self = Self { spheres: Vec::new(), quads: Vec::new(), sphere_count: 0, quad_count: 0 };
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
