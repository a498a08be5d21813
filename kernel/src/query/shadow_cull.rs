//! Which objects can block a shadow ray, receiver by receiver and light by light. A shading
//! point lies on the object a camera ray hit (the receiver), and its shadow ray ends on a light
//! (or, for a BSDF sample, at the light it found): the segment lies in the convex hull of the
//! receiver and the light. An object that no plane leaves on the hull's other side may block it;
//! the others cannot, and the shadow queries skip them ([`Scene::shadow_unoccluded`] and
//! the BSDF ray's occlusion test, [`Scene::emitter_hit_from_surface`]). The answer is the same,
//! bit for bit: only objects that no segment from the receiver to the light meets are skipped.
//!
//! Every shape is a convex set: a quad is the hull of its corners, a sphere its center grown by
//! its radius, a point light a point ([`Convex`]). Two convex sets are disjoint if and only if
//! some axis separates their projections; the test tries a fixed list of axes (the planes' normals,
//! the world axes, the directions between centers and the cross products of the edges with the
//! directions across the hull) and keeps the object when none separates, so it may keep an
//! object that cannot block, never the other way round.
//!
//! The projections are compared with a margin of [`MARGIN`] of the largest coordinate involved
//! (the camera's position included: a shading point's rounding grows with its distance from the
//! camera). The shading point, the point on the light and the ray tests are all within about 1e-7
//! of that scale of the exact geometry.
//!
//! Masks hold objects below [`CULLED`] (one bit each); objects from there on are always tested,
//! and a receiver or a light's shape from there on gets no mask (the full query runs).
//!
//! [`Scene::shadow_unoccluded`]: crate::scene::Scene::shadow_unoccluded
//! [`Scene::emitter_hit_from_surface`]: crate::scene::Scene::emitter_hit_from_surface

use crate::geometry::Shape;
use crate::num::{Vec3, dot, try_normalize};
use crate::query::camera_cull::{CULLED, object_bit};
use crate::words::{Image, Words};

/// Widening of every separation, relative to the largest coordinate involved.
pub const MARGIN: f32 = 1e-4;

/// A convex set: the hull of one or four points, grown by `radius`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Convex {
    points: [Vec3; 4],
    /// How many of `points` count (1 or 4).
    count: usize,
    radius: f32,
    /// A quad's unit normal (zero for the others: an axis that separates nothing).
    normal: Vec3,
    /// The largest magnitude of a coordinate of the set.
    extent: f32,
}

impl Convex {
    /// The set a shape covers. (Out of line: the scene build calls it from a few places.)
    #[inline(never)]
    pub fn of_shape(shape: &Shape) -> Self {
        match shape.corners() {
            Some(p) => {
                let normal = shape.normal_at(p[0]);
                let extent = p.iter().fold(0.0f32, |m, p| m.max(p.abs().max_element()));
                Convex { points: p, count: 4, radius: 0.0, normal, extent }
            }
            None => Convex::ball(shape.centroid(), shape.bounding_radius()),
        }
    }

    /// The point `p` (a point light).
    pub fn point(p: Vec3) -> Self {
        Convex::ball(p, 0.0)
    }

    fn ball(center: Vec3, radius: f32) -> Self {
        let extent = center.abs().max_element() + radius;
        Convex { points: [center; 4], count: 1, radius, normal: Vec3::ZERO, extent }
    }

    /// The center: of a ball, or of a quad's diagonal.
    fn center(&self) -> Vec3 {
        if self.count == 4 { (self.points[0] + self.points[2]) * 0.5 } else { self.points[0] }
    }

    /// A quad's edges from its first corner (zero for the others: axes that separate nothing).
    fn edge(&self, k: usize) -> Vec3 {
        if self.count == 4 { self.points[if k == 0 { 1 } else { 3 }] - self.points[0] } else { Vec3::ZERO }
    }

    /// The projection on the unit axis `a`: `(min, max)`; everything when a product is NaN
    /// (an interval that separates nothing).
    fn interval(&self, a: Vec3) -> (f32, f32) {
        let points = self.points.get(..self.count).unwrap_or(&self.points);
        let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
        for &p in points {
            let x = dot(p, a);
            if x.is_nan() {
                return (f32::NEG_INFINITY, f32::INFINITY);
            }
            // (Compares, not `min` and `max`: those are library calls on the Cortex-M.)
            if x < lo {
                lo = x;
            }
            if x > hi {
                hi = x;
            }
        }
        (lo - self.radius, hi + self.radius)
    }
}

/// Whether `o` may meet a segment from a point of `r` to a point of `l` (see the module docs):
/// false only when an axis separates `o` from the hull of `r` and `l` by more than [`MARGIN`] of
/// `scale` and of the sets' own extents. Non-finite values keep the object. (Out of line: the
/// scene build calls it from a few places.)
#[inline(never)]
pub fn may_block(o: &Convex, r: &Convex, l: &Convex, scale: f32) -> bool {
    let margin = MARGIN * scale.max(o.extent).max(r.extent).max(l.extent);
    !(0..AXES).any(|i| separates(axis(i, o, r, l), o, r, l, margin))
}

/// How many axes [`may_block`] tries.
const AXES: usize = 8 + 3 * 5;

/// Axis `i` of [`may_block`]: the planes' normals and the world axes first (they separate most
/// pairs), the directions between the centers of `o` and the others, then the directions across
/// the hull (between the centers, along the receiver's and the light's edges) crossed with the
/// edges and the normal of `o`. Missing normals and edges are zero: axes that separate nothing.
/// (Out of line, like [`may_block`].)
#[inline(never)]
fn axis(i: usize, o: &Convex, r: &Convex, l: &Convex) -> Vec3 {
    match i {
        0 => o.normal,
        1 => r.normal,
        2 => l.normal,
        3 => Vec3::X,
        4 => Vec3::Y,
        5 => Vec3::Z,
        6 => o.center() - r.center(),
        7 => o.center() - l.center(),
        _ => {
            let (k, d) = ((i - 8) / 5, (i - 8) % 5);
            let k = if k < 2 { o.edge(k) } else { o.normal };
            let d = match d {
                0 => l.center() - r.center(),
                1 | 2 => r.edge(d - 1),
                _ => l.edge(d - 3),
            };
            k.cross(d)
        }
    }
}

/// Whether the axis `a` (any length; zero or not finite: no) separates `o` from the hull of `r`
/// and `l` by more than `margin`. (Out of line, like [`may_block`].)
#[inline(never)]
fn separates(a: Vec3, o: &Convex, r: &Convex, l: &Convex, margin: f32) -> bool {
    let Some(a) = try_normalize(a) else { return false };
    let (oi, ri, li) = (o.interval(a), r.interval(a), l.interval(a));
    let lo = if li.0 < ri.0 { li.0 } else { ri.0 };
    let hi = if li.1 > ri.1 { li.1 } else { ri.1 };
    oi.0 > hi + margin || oi.1 < lo - margin
}

/// The shapes and lights a [`ShadowCull`] is built from: the scene's so far.
pub trait Sets {
    /// How many shapes there are.
    fn shapes(&self) -> usize;
    /// Shape `i`'s set.
    fn shape(&self, i: usize) -> Option<Convex>;
    /// How many lights there are.
    fn lights(&self) -> usize;
    /// Light `l`'s set, and the index of its shape (area lights).
    fn light(&self, l: usize) -> Option<(Convex, Option<usize>)>;
}

/// The mask of a pair that has none: every bit set, which no mask has (it leaves out its receiver
/// or its light's shape, one of which is below [`CULLED`] when the pair has a mask).
const NO_MASK: u32 = u32::MAX;

/// For each receiver and light, the objects that may block a shadow ray between them.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadowCull<const S: usize, const L: usize> {
    /// Bit o of `masks[r][l]`: object o may lie between object r and light l.
    masks: [[u32; L]; S],
    /// Bit o: object o emits.
    emitters: u32,
    /// The largest coordinate of the camera's position (see [`MARGIN`]).
    camera_extent: f32,
}

impl<const S: usize, const L: usize> ShadowCull<S, L> {
    /// No objects or lights yet; the camera at `camera`.
    pub fn new(camera: Vec3) -> Self {
        Self { masks: [[0; L]; S], emitters: 0, camera_extent: camera.abs().max_element() }
    }

    /// Shape `index` has joined `sets` (the last of its shapes): it is the receiver of new
    /// pairs with every light, and it may block the pairs before it. (Out of line: it runs once
    /// per object, when the scene is built.)
    #[inline(never)]
    pub fn add_object(&mut self, index: usize, sets: &impl Sets) {
        let Some(new) = sets.shape(index) else { return };
        for l in 0..sets.lights() {
            let Some((light, emitter)) = sets.light(l) else { continue };
            self.fill(index, l, &new, &light, emitter, sets);
            for r in 0..index.min(CULLED) {
                if let Some(receiver) = sets.shape(r) {
                    self.consider(index, &new, r, &receiver, l, &light, emitter);
                }
            }
        }
    }

    /// Light `light` has joined `sets` (the last of its lights): its pairs with every receiver.
    /// (Out of line: once per light.)
    #[inline(never)]
    pub fn add_light(&mut self, light: usize, sets: &impl Sets) {
        let Some((set, emitter)) = sets.light(light) else { return };
        if let Some(bit) = emitter.and_then(object_bit) {
            self.emitters |= bit;
        }
        for r in 0..sets.shapes().min(CULLED) {
            if let Some(receiver) = sets.shape(r) {
                self.fill(r, light, &receiver, &set, emitter, sets);
            }
        }
    }

    /// The mask of pair (`r`, `l`) from every shape of `sets`. (Out of line: called from two
    /// places.)
    #[inline(never)]
    fn fill(
        &mut self,
        r: usize,
        l: usize,
        receiver: &Convex,
        light: &Convex,
        emitter: Option<usize>,
        sets: &impl Sets,
    ) {
        // A receiver or an emitter from CULLED on would be tested anyway: no mask.
        let masked = r < CULLED && emitter.is_none_or(|e| e < CULLED);
        if let Some(mask) = self.masks.get_mut(r).and_then(|row| row.get_mut(l)) {
            *mask = if masked { 0 } else { NO_MASK };
        }
        if !masked {
            return;
        }
        for o in 0..sets.shapes().min(CULLED) {
            if let Some(set) = sets.shape(o) {
                self.consider(o, &set, r, receiver, l, light, emitter);
            }
        }
    }

    /// Object `o` (`set`) joins pair (`r`, `l`)'s mask if it may block it.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn consider(
        &mut self,
        o: usize,
        set: &Convex,
        r: usize,
        receiver: &Convex,
        l: usize,
        light: &Convex,
        emitter: Option<usize>,
    ) {
        if o == r || Some(o) == emitter || !may_block(set, receiver, light, self.camera_extent) {
            return;
        }
        if let (Some(bit), Some(mask)) = (object_bit(o), self.masks.get_mut(r).and_then(|row| row.get_mut(l)))
        {
            *mask |= bit;
        }
    }

    /// The objects that may block a shadow ray from a point of object `receiver` to light
    /// `light`, neither the receiver nor the light's shape among them: a mask for
    /// [`Filter::Among`](crate::query::accel::Filter::Among). `None` when the pair has no mask (a
    /// receiver or a light's shape from [`CULLED`] on, or an unknown pair).
    #[inline]
    pub fn occluders(&self, receiver: usize, light: usize) -> Option<u32> {
        self.masks.get(receiver)?.get(light).copied().filter(|&m| m != NO_MASK)
    }

    /// The objects a culled shadow or BSDF ray from a point of object `receiver` may test: the
    /// emitters and every light's occluders (bit o for object o; every object when a pair has
    /// no mask).
    #[inline]
    pub fn reachable(&self, receiver: usize) -> u32 {
        match self.masks.get(receiver) {
            Some(row) => row.iter().fold(self.emitters, |all, &m| all | m),
            None => u32::MAX,
        }
    }

    /// [`ShadowCull::occluders`] that do not emit.
    #[inline]
    pub fn other_occluders(&self, receiver: usize, light: usize) -> Option<u32> {
        self.occluders(receiver, light).map(|m| m & !self.emitters)
    }
}

impl<const S: usize, const L: usize> ShadowCull<S, L> {
    /// No objects, no lights, for a scene that is about to be loaded.
    pub(crate) const EMPTY: Self = ShadowCull { masks: [[0; L]; S], emitters: 0, camera_extent: 0.0 };

    /// Writes the masks of the first `shapes` receivers and `lights` lights to `out`.
    pub(crate) fn put(&self, shapes: usize, lights: usize, out: &mut dyn FnMut(u32)) {
        out(self.emitters);
        self.camera_extent.put(out);
        for row in self.masks.iter().take(shapes) {
            row.iter().take(lights).for_each(|&m| out(m));
        }
    }

    /// Reads what [`ShadowCull::put`] wrote for `shapes` receivers and `lights` lights (each at
    /// most the capacity).
    pub(crate) fn get(&mut self, shapes: usize, lights: usize, w: &mut Words<'_>) -> Option<()> {
        *self = Self::EMPTY;
        self.emitters = w.u32()?;
        self.camera_extent = w.f32()?;
        for r in 0..shapes {
            for l in 0..lights {
                *self.masks.get_mut(r)?.get_mut(l)? = w.u32()?;
            }
        }
        Some(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Ray;
    use crate::num::Vec2;
    use crate::sampling::sample_uniform_sphere;
    use crate::sampling::sampler::Sampler;

    fn quad(p0: Vec3, e1: Vec3, e2: Vec3) -> Shape {
        Shape::quad([p0, p0 + e1, p0 + e1 + e2, p0 + e2]).unwrap()
    }

    /// A point of `shape`: on its surface, or for a sphere anywhere in its ball.
    fn point_of(shape: &Shape, u: Vec2, w: f32) -> Vec3 {
        match shape.corners() {
            Some(p) => p[0] + (p[1] - p[0]) * u.x + (p[3] - p[0]) * u.y,
            None => shape.centroid() + sample_uniform_sphere(u) * (shape.bounding_radius() * w),
        }
    }

    fn random_shape(rng: &mut Sampler) -> Shape {
        let p = |rng: &mut Sampler| {
            let (a, b) = (rng.next_2d(), rng.next_2d());
            Vec3::new(a.x, a.y, b.x) * 8.0 - Vec3::splat(4.0)
        };
        if rng.next_2d().x < 0.5 {
            Shape::sphere(p(rng), 0.05 + 2.0 * rng.next_2d().x).unwrap()
        } else {
            quad(p(rng), p(rng) * 0.7, p(rng) * 0.7)
        }
    }

    /// Random triples of shapes: every segment from the receiver to the light that the ray test
    /// finds blocked by the third shape has it kept, and some triples are culled (the test can
    /// fail both ways).
    #[test]
    fn a_shape_that_blocks_a_segment_is_kept() {
        let mut rng = Sampler::new(11, 1, 1);
        let (mut blocked, mut culled) = (0, 0);
        for _ in 0..3000 {
            let (o, r, l) = (random_shape(&mut rng), random_shape(&mut rng), random_shape(&mut rng));
            let keeps = may_block(&Convex::of_shape(&o), &Convex::of_shape(&r), &Convex::of_shape(&l), 0.0);
            culled += usize::from(!keeps);
            for _ in 0..64 {
                let x = point_of(&r, rng.next_2d(), 1.0);
                let y = point_of(&l, rng.next_2d(), rng.next_2d().x);
                let Some(dir) = try_normalize(y - x) else { continue };
                let t = (y - x).length();
                if o.intersect(&Ray { origin: x, dir }, 0.0, t).is_some() {
                    blocked += 1;
                    assert!(keeps, "{o:?} blocks {x} -> {y} ({r:?} to {l:?}) but was culled");
                }
            }
        }
        println!("{blocked} blocked segments, {culled} of 3000 triples culled");
        assert!(blocked > 1000 && culled > 500, "{blocked} blocked segments, {culled} triples culled");
    }

    #[test]
    fn separated_shapes_are_culled_and_touching_ones_kept() {
        let floor = Convex::of_shape(&quad(Vec3::new(-1.0, 0.0, 1.0), Vec3::X * 2.0, Vec3::Z * -2.0));
        let light = Convex::of_shape(&Shape::sphere(Vec3::new(0.0, 2.0, 0.0), 0.5).unwrap());
        // Below the floor, beside the light, and between them.
        let below = Convex::of_shape(&Shape::sphere(Vec3::new(0.0, -1.0, 0.0), 0.5).unwrap());
        let beside = Convex::of_shape(&Shape::sphere(Vec3::new(3.0, 2.0, 0.0), 0.5).unwrap());
        let between = Convex::of_shape(&Shape::sphere(Vec3::new(0.3, 1.0, 0.2), 0.1).unwrap());
        assert!(!may_block(&below, &floor, &light, 1.0));
        assert!(!may_block(&beside, &floor, &light, 1.0));
        assert!(may_block(&between, &floor, &light, 1.0));
        // Touching the floor from below: kept (the margin), a hair farther: culled.
        let touching = Convex::of_shape(&Shape::sphere(Vec3::new(0.0, -0.5, 0.0), 0.5).unwrap());
        let apart = Convex::of_shape(&Shape::sphere(Vec3::new(0.0, -0.51, 0.0), 0.5).unwrap());
        assert!(may_block(&touching, &floor, &light, 1.0));
        assert!(!may_block(&apart, &floor, &light, 1.0));
        // A point light.
        assert!(!may_block(&below, &floor, &Convex::point(Vec3::Y), 1.0));
    }

    /// Shapes, the first `n` of them in the scene, and lights on some of them, the first `m`.
    struct TestSets<'a> {
        shapes: &'a [Shape],
        n: usize,
        lights: &'a [usize],
        m: usize,
    }

    impl Sets for TestSets<'_> {
        fn shapes(&self) -> usize {
            self.n
        }
        fn shape(&self, i: usize) -> Option<Convex> {
            self.shapes.get(..self.n)?.get(i).map(Convex::of_shape)
        }
        fn lights(&self) -> usize {
            self.m
        }
        fn light(&self, l: usize) -> Option<(Convex, Option<usize>)> {
            let &e = self.lights.get(..self.m)?.get(l)?;
            Some((self.shape(e)?, Some(e)))
        }
    }

    #[test]
    fn masks_do_not_depend_on_the_order_of_building() {
        let mut rng = Sampler::new(3, 1, 1);
        let shapes: [Shape; 8] = core::array::from_fn(|_| random_shape(&mut rng));
        let lights = [1usize, 4, 6];
        let sets = |n, m| TestSets { shapes: &shapes, n, lights: &lights, m };
        // All shapes first, then the lights.
        let mut a = ShadowCull::<8, 3>::new(Vec3::ZERO);
        for i in 0..8 {
            a.add_object(i, &sets(i + 1, 0));
        }
        for l in 0..3 {
            a.add_light(l, &sets(8, l + 1));
        }
        // Lights as soon as their shapes are there.
        let mut b = ShadowCull::<8, 3>::new(Vec3::ZERO);
        let mut m = 0;
        for i in 0..8 {
            b.add_object(i, &sets(i + 1, m));
            if lights.get(m) == Some(&i) {
                m += 1;
                b.add_light(m - 1, &sets(i + 1, m));
            }
        }
        assert_eq!(a, b);
        assert!(a.masks.iter().flatten().any(|&m| m != 0) && a.masks.iter().flatten().any(|&m| m == 0));
        assert_eq!(a.occluders(0, 0), Some(a.masks[0][0]));
        assert_eq!(a.occluders(0, 3), None);
        assert_eq!(a.other_occluders(0, 1).map(|m| m & (1 << 6 | 1 << 1)), Some(0));
    }
}
