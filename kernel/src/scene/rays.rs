//! The scene's ray queries: the nearest hit, the camera's rays (culled by tile), the first
//! emitter along a BSDF sample's ray, and the visibility of a shadow ray (culled by receiver and
//! light), in f32 through the packets of `query/` or in fixed point.

use crate::geometry::{Ray, SurfacePoint};
use crate::num::{Rgb, Vec2, Vec3, dot};
use crate::query::accel::{self, Filter, PointRays, RaysFrom};
use crate::query::camera_cull::object_bit;
#[cfg(feature = "fixed")]
use crate::scene::Object;
use crate::scene::{Hit, Light, LightId, Scene, ShapeId};

impl<const S: usize, const L: usize, const M: usize> Scene<S, L, M> {
    /// The nearest hit in `(t_min, t_max)`, ignoring object `skip`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32, skip: Option<ShapeId>) -> Option<Hit> {
        self.query(ray, t_min, t_max, Filter::AllBut(skip.map_or(usize::MAX, ShapeId::index)))
    }

    /// The nearest hit beyond `t_near` of the camera ray `ray` through pixel `(x, y)`: that of
    /// [`Scene::intersect`], bit for bit, with the tests of the objects no camera ray through
    /// the pixel's tile of the film can hit left out (`CameraCull`), in f32 and in fixed
    /// point alike.
    #[inline]
    pub fn intersect_camera(&self, ray: &Ray, t_near: f32, x: u32, y: u32) -> Option<Hit> {
        self.query(ray, t_near, f32::INFINITY, Filter::Among(self.camera_candidates(x, y)))
    }

    /// The camera ray through pixel position `p` in pixel `(x, y)` and its nearest hit beyond the
    /// clip plane: [`Scene::intersect_camera`] of [`Camera::ray_at_pixel`]'s ray, without checking
    /// that the ray starts at the camera (it does).
    #[inline]
    pub(crate) fn camera_hit(&self, p: Vec2, x: u32, y: u32) -> (Ray, Option<Hit>) {
        let (ray, t_near) = self.camera.ray_at_pixel(p);
        let filter = Filter::Among(self.camera_candidates(x, y));
        let hit = if accel::ENABLED {
            self.query(&ray, t_near, f32::INFINITY, filter)
        } else {
            self.intersect_from(&self.camera_rays, ray.dir, t_near, f32::INFINITY, filter)
        };
        (ray, hit)
    }

    /// The objects a camera ray through pixel `(x, y)` may hit: bit i for object i (objects
    /// from `CULLED` on may always be hit).
    #[inline]
    pub fn camera_candidates(&self, x: u32, y: u32) -> u32 {
        self.camera_cull.candidates(x, y)
    }

    /// The nearest hit in `(t_min, t_max)` among the objects `filter` admits (every one but
    /// one, or a camera ray's candidates).
    #[inline]
    fn query(&self, ray: &Ray, t_min: f32, t_max: f32, filter: Filter) -> Option<Hit> {
        // Hosted targets keep no origin terms (their packets need none): any ray goes straight
        // to the query, without comparing its origin with the camera's (a comparison that also
        // stalled on x86, reading the just-stored origin back in one wider load).
        if accel::ENABLED {
            return self.intersect_from(
                &RaysFrom::<S, false>::new(ray.origin),
                ray.dir,
                t_min,
                t_max,
                filter,
            );
        }
        // A camera ray (the camera's origin, bit for bit) takes the terms the scene keeps.
        if self.camera_rays.start_at(ray.origin) {
            return self.intersect_from(&self.camera_rays, ray.dir, t_min, t_max, filter);
        }
        self.with_rays_from(ray.origin, |from| self.intersect_from(from, ray.dir, t_min, t_max, filter))
    }

    /// [`Scene::query`] for the ray from `from` along `dir`.
    #[inline(always)]
    fn intersect_from<const K: bool>(
        &self,
        from: &RaysFrom<S, K>,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
        filter: Filter,
    ) -> Option<Hit> {
        #[cfg(feature = "fixed")]
        if self.fixed.is_on() {
            // (The queries for emitters or non-emitters have fixed-point branches of their own.)
            let keep = |i: usize| match filter {
                Filter::AllBut(skip) => i != skip,
                Filter::Among(m) => accel::among_holds(m, i),
                _ => true,
            };
            let ray = from.ray(dir);
            let (t, i) = self.fixed.nearest(&self.objects, &ray, t_min, t_max, false, keep)?;
            return self.hit(&ray, t, i);
        }
        let (t, i) = self.packets.nearest(from, dir, t_min, t_max, filter, &self.objects)?;
        self.hit(&from.ray(dir), t, i)
    }

    /// `f` of the rays from the point `origin` (a shading point's shadow and BSDF rays), for
    /// the queries that take them.
    #[inline(always)]
    pub(crate) fn with_rays_from<R>(&self, origin: Vec3, f: impl FnOnce(&PointRays<S>) -> R) -> R {
        self.with_rays_among(origin, u32::MAX, f)
    }

    /// The objects that the culled queries of the shadow and BSDF rays from a point of object
    /// `receiver` may test ([`Scene::unoccluded_from`] with a light, [`Scene::emitter_hit_from`]
    /// with `SURFACE`): bit i for object i ([`ShadowCull::reachable`]).
    #[inline]
    pub(crate) fn reachable(&self, receiver: ShapeId) -> u32 {
        self.shadow_cull.reachable(receiver.index())
    }

    /// [`Scene::with_rays_from`] with the origin terms of the objects in `among` only (bit i for
    /// object i below 32; every object from there on), for queries that test no other.
    #[inline(always)]
    pub(crate) fn with_rays_among<R>(
        &self,
        origin: Vec3,
        among: u32,
        f: impl FnOnce(&PointRays<S>) -> R,
    ) -> R {
        // The fixed-point queries do not read the f32 origin terms: none are computed.
        #[cfg(feature = "fixed")]
        let objects: &[Object] = if self.fixed.is_on() { &[] } else { &self.objects };
        #[cfg(not(feature = "fixed"))]
        let objects = &self.objects;
        PointRays::with_among(origin, objects.iter().map(|o| &o.shape), among, f)
    }

    /// The [`Hit`] record for object `object` at distance `t` along `ray`.
    #[inline]
    fn hit(&self, ray: &Ray, t: f32, object: usize) -> Option<Hit> {
        let shape = &self.objects.get(object)?.shape;
        let p = ray.at(t);
        let n = shape.normal_at(p);
        let object = ShapeId::new(object as u16); // < S, and S shapes have u16 indices
        Some(Hit { t, object, point: SurfacePoint { p, n }, front: dot(n, ray.dir) < 0.0 })
    }

    /// The first surface along `ray` (ignoring object `skip`) if it is an emitter's front side:
    /// the emitting hit, its light and radiance. Cheaper than [`Scene::intersect`]: the
    /// closest emitter is found first, then only an any-hit occlusion test by the other objects
    /// runs up to it, so rays that miss every light test only the emitters.
    #[inline]
    pub fn emitter_hit(&self, ray: &Ray, skip: ShapeId) -> Option<(Hit, LightId, Rgb)> {
        self.with_rays_from(ray.origin, |from| self.emitter_hit_from::<false>(from, ray.dir, skip))
    }

    /// [`Scene::emitter_hit`] for a ray that leaves a point of object `receiver` (a BSDF sample's
    /// ray): the same answer, with the occlusion test skipping the objects that cannot lie
    /// between the receiver and the light found (`ShadowCull`). For rays from elsewhere the
    /// answer may differ: use [`Scene::emitter_hit`].
    #[inline]
    pub fn emitter_hit_from_surface(&self, ray: &Ray, receiver: ShapeId) -> Option<(Hit, LightId, Rgb)> {
        self.with_rays_from(ray.origin, |from| self.emitter_hit_from::<true>(from, ray.dir, receiver))
    }

    /// [`Scene::emitter_hit`] for the ray from `from` along `dir`; with `SURFACE`,
    /// [`Scene::emitter_hit_from_surface`] (`from` is on object `skip`).
    #[inline]
    pub(crate) fn emitter_hit_from<const SURFACE: bool>(
        &self,
        from: &PointRays<S>,
        dir: Vec3,
        skip: ShapeId,
    ) -> Option<(Hit, LightId, Rgb)> {
        let skip = skip.index();
        #[cfg(feature = "fixed")]
        if self.fixed.is_on() {
            // The first surface, if it is an emitter's front side. From a point of `skip`, among
            // the objects the culled queries may test only: an object that no segment from
            // there to a light can meet is never before an emitter on the ray.
            let reachable = if SURFACE { self.shadow_cull.reachable(skip) } else { u32::MAX };
            let keep = |i| i != skip && accel::among_holds(reachable, i);
            let ray = from.ray(dir);
            let (t, best) = self.fixed.nearest(&self.objects, &ray, 0.0, f32::INFINITY, false, keep)?;
            let hit = self.hit(&ray, t, best).filter(|h| h.front)?;
            let light = self.objects.get(best)?.light?;
            return match self.lights.get(light.index())? {
                Light::Area { radiance, .. } => Some((hit, light, *radiance)),
                Light::Point { .. } => None,
            };
        }
        let emitters = Filter::EmittersBut(skip);
        let (t, best) = self.packets.nearest(from, dir, 0.0, f32::INFINITY, emitters, &self.objects)?;
        let hit = self.hit(&from.ray(dir), t, best)?;
        if !hit.front {
            return None; // the back of an emitter: it emits nothing this way
        }
        // Anything else in front of it? (Emitters were already compared above.)
        let light = self.objects.get(best)?.light?;
        let culled = if SURFACE { self.shadow_cull.other_occluders(skip, light.index()) } else { None };
        let others = culled.map_or(Filter::OthersBut(skip), Filter::Among);
        if self.packets.any(from, dir, 0.0, t, others, &self.objects) {
            return None;
        }
        match self.lights.get(light.index())? {
            Light::Area { radiance, .. } => Some((hit, light, *radiance)),
            Light::Point { .. } => None,
        }
    }

    /// Calls `f` for every emitter whose front side `ray` meets (ignoring object `skip`), with the
    /// hit, the light, its radiance, and whether it is the first surface on the ray (visible).
    /// For the control variate, which needs the lights behind occluders too.
    #[inline]
    pub fn emitters_along(&self, ray: &Ray, skip: ShapeId, f: impl FnMut(Hit, LightId, Rgb, bool)) {
        self.with_rays_from(ray.origin, |from| self.emitters_along_from(from, ray.dir, skip, f));
    }

    /// [`Scene::emitters_along`] for the ray from `from` along `dir`.
    #[inline]
    pub(crate) fn emitters_along_from(
        &self,
        from: &PointRays<S>,
        dir: Vec3,
        skip: ShapeId,
        mut f: impl FnMut(Hit, LightId, Rgb, bool),
    ) {
        let ray = from.ray(dir);
        // Whether an emitter is the first surface on the ray: only the objects that may lie
        // between the receiver and some light can be in front of one (the shadow cull), so the
        // nearest among them answers it for every emitter, as the nearest among all would.
        let filter = match object_bit(skip.index()) {
            Some(bit) => Filter::Among(self.shadow_cull.reachable(skip.index()) & !bit),
            None => Filter::AllBut(skip.index()),
        };
        let nearest = self.intersect_from(from, dir, 0.0, f32::INFINITY, filter).map(|h| h.object);
        for (i, o) in self.objects.iter().enumerate() {
            let Some(light) = o.light else { continue };
            if i == skip.index() {
                continue;
            }
            #[cfg(feature = "fixed")]
            let t = if self.fixed.is_on() {
                self.fixed.intersect(i, &o.shape, &ray, 0.0, f32::INFINITY)
            } else {
                o.shape.intersect(&ray, 0.0, f32::INFINITY)
            };
            #[cfg(not(feature = "fixed"))]
            let t = o.shape.intersect(&ray, 0.0, f32::INFINITY);
            let Some(t) = t else { continue };
            let Some(hit) = self.hit(&ray, t, i).filter(|h| h.front) else { continue };
            if let Some(Light::Area { radiance, .. }) = self.lights.get(light.index()) {
                f(hit, light, *radiance, nearest == Some(hit.object));
            }
        }
    }

    /// True when nothing but objects `a` and `b` lies on the ray before `t_max`.
    #[inline]
    pub fn unoccluded(&self, ray: &Ray, t_max: f32, a: ShapeId, b: Option<ShapeId>) -> bool {
        self.with_rays_from(ray.origin, |from| self.unoccluded_from(from, ray.dir, t_max, a, b, None))
    }

    /// [`Scene::unoccluded`] for a shadow ray from a point of object `receiver` to a point of
    /// light `light` at `t_max` (skipping the receiver and the light's shape): the same answer,
    /// testing only the objects that may lie between the two (`ShadowCull`). For rays from
    /// elsewhere, or to other points, the answer may differ: use [`Scene::unoccluded`].
    #[inline]
    pub fn shadow_unoccluded(&self, ray: &Ray, t_max: f32, receiver: ShapeId, light: LightId) -> bool {
        let emitter = self.light(light).and_then(Light::shape);
        self.with_rays_from(ray.origin, |from| {
            self.unoccluded_from(from, ray.dir, t_max, receiver, emitter, Some(light))
        })
    }

    /// The objects that may block a shadow ray from a point of object `receiver` to light
    /// `light`: bit i for object i (objects from `CULLED` on, and
    /// every object when the pair has no mask, may always block; the receiver and the light's
    /// shape never do).
    #[inline]
    pub fn shadow_candidates(&self, receiver: ShapeId, light: LightId) -> u32 {
        self.shadow_cull.occluders(receiver.index(), light.index()).unwrap_or(u32::MAX)
    }

    /// [`Scene::unoccluded`] for the ray from `from` along `dir`; with `light`,
    /// [`Scene::shadow_unoccluded`] (`from` is on object `a`, and `b` is the light's shape).
    #[inline]
    pub(crate) fn unoccluded_from(
        &self,
        from: &PointRays<S>,
        dir: Vec3,
        t_max: f32,
        a: ShapeId,
        b: Option<ShapeId>,
        light: Option<LightId>,
    ) -> bool {
        let culled = light.and_then(|l| self.shadow_cull.occluders(a.index(), l.index()));
        #[cfg(feature = "fixed")]
        if self.fixed.is_on() {
            let (ia, ib) = (a.index(), b.map_or(usize::MAX, ShapeId::index));
            let keep = |i| i != ia && i != ib && culled.is_none_or(|m| accel::among_holds(m, i));
            return self.fixed.nearest(&self.objects, &from.ray(dir), 0.0, t_max, true, keep).is_none();
        }
        let others =
            culled.map_or(Filter::AllButTwo(a.index(), b.map_or(usize::MAX, ShapeId::index)), Filter::Among);
        !self.packets.any(from, dir, 0.0, t_max, others, &self.objects)
    }
}
