//! A scene in fixed-capacity storage: `S` shapes, `L` lights, `M` materials, chosen by the user
//! of the kernel (a firmware build uses exactly its scene's counts). Every value is validated as
//! it is added; a full collection is an error, never a panic. The scene builds and answers ray
//! queries; choosing and sampling lights is the light sampler's job (`light/`).

mod ids;
mod light;
mod material;

pub use ids::{LightId, MaterialId, ShapeId};
pub use light::{Emission, Light, MAX_EMISSION};
pub use material::{BsdfSample, Material, Outgoing};

use heapless::Vec;

use crate::error::{Collection, SceneError};
use crate::geometry::{Camera, CameraDesc, Film};
use crate::geometry::{Ray, Shape, SurfacePoint};
use crate::image::{Image, Words};
use crate::num::{Rgb, Vec2, Vec3, dot};
#[cfg(feature = "fixed")]
use crate::query::Arith;
use crate::query::accel::{self, CameraRays, Filter, Packets, PointRays, RaysFrom, Target};
use crate::query::camera_cull::CameraCull;
#[cfg(feature = "fixed")]
use crate::query::fixed::FixedScene;
use crate::query::shadow_cull::{Convex, Sets, ShadowCull};

/// A shape with its material and, if it emits, its light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Object {
    /// Geometry.
    pub shape: Shape,
    material: MaterialId,
    light: Option<LightId>,
}

impl Target for Object {
    #[inline]
    fn shape(&self) -> &Shape {
        &self.shape
    }
    #[inline]
    fn emits(&self) -> bool {
        self.light.is_some()
    }
}

/// The first surface a ray meets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the ray.
    pub t: f32,
    /// The object (shape) hit.
    pub object: ShapeId,
    /// Position and front-side normal.
    pub point: SurfacePoint,
    /// True when the ray arrived on the front side.
    pub front: bool,
}

/// A scene with room for `S` shapes, `L` lights and `M` materials.
#[derive(Clone, Debug)]
pub struct Scene<const S: usize, const L: usize, const M: usize> {
    camera: Camera,
    film: Film,
    objects: Vec<Object, S>,
    /// The shapes again, four to a packet, for ray queries (hosted targets; microcontrollers
    /// keep only the span of the emitters' indices there).
    packets: Packets<S>,
    /// The camera's rays, with the origin terms of every object on microcontrollers.
    camera_rays: CameraRays<S>,
    /// The objects the camera's rays may hit, tile by tile of the film.
    camera_cull: CameraCull,
    /// The objects that may block a shadow ray, per receiver and light.
    shadow_cull: ShadowCull<S, L>,
    materials: Vec<Material, M>,
    lights: Vec<Light, L>,
    /// The fixed-point copies of the shapes while the ray queries run in fixed point
    /// ([`Scene::enable_arith`]; empty otherwise), filled in place.
    #[cfg(feature = "fixed")]
    fixed: FixedScene<S>,
}

/// The scene's shapes and lights as [`ShadowCull`] sees them.
struct SceneSets<'a> {
    objects: &'a [Object],
    lights: &'a [Light],
}

// Out of line: the scene build calls them from a few places.
impl Sets for SceneSets<'_> {
    fn shapes(&self) -> usize {
        self.objects.len()
    }
    #[inline(never)]
    fn shape(&self, i: usize) -> Option<Convex> {
        self.objects.get(i).map(|o| Convex::of_shape(&o.shape))
    }
    fn lights(&self) -> usize {
        self.lights.len()
    }
    #[inline(never)]
    fn light(&self, l: usize) -> Option<(Convex, Option<usize>)> {
        match *self.lights.get(l)? {
            Light::Area { shape, .. } => Some((self.shape(shape.index())?, Some(shape.index()))),
            Light::Point { position, .. } => Some((Convex::point(position), None)),
        }
    }
}

/// The first word of a scene image ([`Scene::write_image`]): "PMI" and the version of the image
/// format, 1.
const IMAGE_MAGIC: u32 = u32::from_be_bytes(*b"PMI\x01");

fn index16(len: usize, what: Collection) -> Result<u16, SceneError> {
    u16::try_from(len).map_err(|_| SceneError::CapacityExceeded(what))
}

impl<const S: usize, const L: usize, const M: usize> Scene<S, L, M> {
    /// An empty scene seen by `camera` on `film`.
    pub fn new(camera: CameraDesc, film: Film) -> Result<Self, SceneError> {
        Ok(Self {
            camera: Camera::new(camera, film)?,
            camera_rays: CameraRays::new(camera.origin),
            camera_cull: CameraCull::new(film),
            shadow_cull: ShadowCull::new(camera.origin),
            film,
            objects: Vec::new(),
            packets: Packets::default(),
            materials: Vec::new(),
            lights: Vec::new(),
            #[cfg(feature = "fixed")]
            fixed: FixedScene::off(),
        })
    }

    /// A scene with nothing in it, not even a camera that sees: the value a scene holds before
    /// [`Scene::load_image`] fills it (a `static` can start from it).
    pub const EMPTY: Self = Self {
        camera: Camera::EMPTY,
        film: Film::ONE,
        objects: Vec::new(),
        packets: Packets::EMPTY,
        camera_rays: CameraRays::new(Vec3::ZERO),
        camera_cull: CameraCull::EMPTY,
        shadow_cull: ShadowCull::EMPTY,
        materials: Vec::new(),
        lights: Vec::new(),
        #[cfg(feature = "fixed")]
        fixed: FixedScene::off(),
    };

    /// Writes the built scene to `out` as 32-bit words ([`crate::image`]): its materials,
    /// objects and lights with every value they derive, its camera and film, and what its ray
    /// queries cull. [`Scene::load_image`] reads them back into a scene of any capacity that
    /// holds them, bit for bit.
    pub fn write_image(&self, out: &mut dyn FnMut(u32)) {
        out(IMAGE_MAGIC);
        out(self.materials.len() as u32);
        self.materials.iter().for_each(|m| m.put(out));
        out(self.objects.len() as u32);
        for o in &self.objects {
            o.shape.put(out);
            out(u32::from(o.material.raw()));
            out(o.light.map_or(u32::MAX, |l| u32::from(l.raw())));
        }
        out(self.lights.len() as u32);
        self.lights.iter().for_each(|l| l.put(out));
        self.camera.put(out);
        self.film.put(out);
        self.camera_cull.put(out);
        self.shadow_cull.put(self.objects.len(), self.lights.len(), out);
    }

    /// Fills this scene, in place, with the scene of `image` ([`Scene::write_image`]): no value
    /// is validated again and no cull computed again, so a firmware that loads its scene this
    /// way carries none of that code. The image's structure is checked (counts against the
    /// capacities, kinds, every index names an entry, each emitter and its light name each
    /// other): anything else is [`SceneError::BadImage`], and the scene is then empty. Ray
    /// queries run in f32 ([`Scene::enable_arith`] after loading for fixed point).
    pub fn load_image(&mut self, image: &[u32]) -> Result<(), SceneError> {
        let loaded = self.read_image(&mut Words::new(image));
        if loaded.is_none() {
            *self = Self::EMPTY;
        }
        loaded.ok_or(SceneError::BadImage)
    }

    /// [`Scene::load_image`]'s reading; `None` where the words do not hold a scene.
    fn read_image(&mut self, w: &mut Words<'_>) -> Option<()> {
        *self = Self::EMPTY;
        if w.u32()? != IMAGE_MAGIC {
            return None;
        }
        for _ in 0..w.count(M)? {
            self.materials.push(Material::get(w)?).ok()?;
        }
        let objects = w.count(S)?;
        for i in 0..objects {
            let shape = Shape::get(w)?;
            let material = MaterialId::new(u16::try_from(w.u32()?).ok()?);
            let light = match w.u32()? {
                u32::MAX => None,
                l => Some(LightId::new(u16::try_from(l).ok()?)),
            };
            if material.index() >= self.materials.len() {
                return None;
            }
            self.objects.push(Object { shape, material, light }).ok()?;
            self.packets.push(i, &shape);
        }
        let lights = w.count(L)?;
        for l in 0..lights {
            let light = Light::get(w)?;
            if let Light::Area { shape, .. } = light {
                // The emitter and its light name each other.
                if self.objects.get(shape.index())?.light != Some(LightId::new(l as u16)) {
                    return None;
                }
                self.packets.set_emitter(shape.index());
            }
            self.lights.push(light).ok()?;
        }
        // Every emitting object's light is an area light on it.
        for (i, o) in self.objects.iter().enumerate() {
            if let Some(l) = o.light {
                if self.lights.get(l.index())?.shape() != Some(ShapeId::new(i as u16)) {
                    return None;
                }
            }
        }
        self.camera = Camera::get(w)?;
        self.film = Film::get(w)?;
        self.camera_rays = CameraRays::new(self.camera.desc().origin);
        for o in &self.objects {
            self.camera_rays.push(&o.shape);
        }
        self.camera_cull = CameraCull::get(w)?;
        self.shadow_cull.get(objects, lights, w)?;
        w.is_empty().then_some(())
    }

    /// Changes the film resolution (the camera keeps its field of view).
    pub fn set_film(&mut self, film: Film) -> Result<(), SceneError> {
        self.camera = Camera::new(self.camera.desc(), film)?;
        self.film = film;
        self.camera_cull = CameraCull::new(film);
        for (i, o) in self.objects.iter().enumerate() {
            self.camera_cull.add(i, &self.camera, &o.shape);
        }
        Ok(())
    }

    /// Adds a material.
    pub fn add_material(&mut self, material: Material) -> Result<MaterialId, SceneError> {
        let id = index16(self.materials.len(), Collection::Materials)?;
        self.materials.push(material).map_err(|_| SceneError::CapacityExceeded(Collection::Materials))?;
        Ok(MaterialId::new(id))
    }

    /// Adds a shape that reflects with `material`.
    pub fn add_shape(&mut self, shape: Shape, material: MaterialId) -> Result<ShapeId, SceneError> {
        if material.index() >= self.materials.len() {
            return Err(SceneError::UnknownMaterial);
        }
        let id = index16(self.objects.len(), Collection::Shapes)?;
        // In fixed point the new shape may change the scale: all are checked before anything is
        // added, so that a shape the format cannot represent leaves the scene as it was.
        #[cfg(feature = "fixed")]
        if self.fixed.is_on() {
            let shapes = self.objects.iter().map(|o| &o.shape).chain(core::iter::once(&shape));
            FixedScene::<S>::check(shapes, self.camera.desc().origin)?;
        }
        self.objects
            .push(Object { shape, material, light: None })
            .map_err(|_| SceneError::CapacityExceeded(Collection::Shapes))?;
        self.packets.push(usize::from(id), &shape);
        self.camera_rays.push(&shape);
        self.camera_cull.add(usize::from(id), &self.camera, &shape);
        self.shadow_cull
            .add_object(usize::from(id), &SceneSets { objects: &self.objects, lights: &self.lights });
        #[cfg(feature = "fixed")]
        if self.fixed.is_on() {
            self.fixed.turn_on(self.objects.iter().map(|o| &o.shape), self.camera.desc().origin)?;
        }
        Ok(ShapeId::new(id))
    }

    /// Makes shape `shape` an area emitter of constant `radiance` on its front side.
    pub fn add_area_light(&mut self, shape: ShapeId, radiance: Rgb) -> Result<LightId, SceneError> {
        let light = Light::area(shape, radiance)?;
        let object = self.objects.get(shape.index()).ok_or(SceneError::UnknownShape)?;
        if object.light.is_some() {
            return Err(SceneError::AlreadyEmitting);
        }
        let id = self.push_light(light)?;
        if let Some(object) = self.objects.get_mut(shape.index()) {
            object.light = Some(id);
        }
        self.packets.set_emitter(shape.index());
        Ok(id)
    }

    /// Adds a point light of radiant `intensity` at `position`.
    pub fn add_point_light(&mut self, position: Vec3, intensity: Rgb) -> Result<LightId, SceneError> {
        let light = Light::point(position, intensity)?;
        self.push_light(light)
    }

    fn push_light(&mut self, light: Light) -> Result<LightId, SceneError> {
        let id = index16(self.lights.len(), Collection::Lights)?;
        let full = SceneError::CapacityExceeded(Collection::Lights);
        self.lights.push(light).map_err(|_| full)?;
        self.shadow_cull
            .add_light(usize::from(id), &SceneSets { objects: &self.objects, lights: &self.lights });
        Ok(LightId::new(id))
    }

    /// Runs the ray queries in `arith` from now on (shading stays f32; feature `fixed`).
    /// [`Arith::Fixed`] picks the scale from the scene's extent and fills the fixed-point copies
    /// of the shapes in place; it fails with [`SceneError::NotRepresentable`], naming the shape,
    /// when the format cannot represent the scene accurately, and the queries then run in f32.
    /// Shapes added later are checked as they are added.
    #[cfg(feature = "fixed")]
    pub fn enable_arith(&mut self, arith: Arith) -> Result<(), SceneError> {
        match arith {
            Arith::F32 => {
                self.fixed.turn_off();
                Ok(())
            }
            Arith::Fixed => {
                self.fixed.turn_on(self.objects.iter().map(|o| &o.shape), self.camera.desc().origin)
            }
        }
    }

    /// Whether `arith` can represent this scene (`Err` names the shape that it cannot; feature
    /// `fixed`).
    #[cfg(feature = "fixed")]
    pub fn supports(&self, arith: Arith) -> Result<(), SceneError> {
        match arith {
            Arith::F32 => Ok(()),
            Arith::Fixed => {
                FixedScene::<S>::check(self.objects.iter().map(|o| &o.shape), self.camera.desc().origin)
            }
        }
    }

    /// The arithmetic of the ray queries (feature `fixed`).
    #[cfg(feature = "fixed")]
    pub fn arith(&self) -> Arith {
        if self.fixed.is_on() { Arith::Fixed } else { Arith::F32 }
    }

    /// The camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }
    /// The film.
    pub fn film(&self) -> Film {
        self.film
    }
    /// All objects (shapes with their materials).
    pub fn objects(&self) -> &[Object] {
        &self.objects
    }
    /// All lights.
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }
    /// All materials.
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// Light `light`.
    #[inline]
    pub fn light(&self, light: LightId) -> Option<&Light> {
        self.lights.get(light.index())
    }

    /// The material of object `object`.
    #[inline]
    pub fn material(&self, object: ShapeId) -> Option<&Material> {
        let o = self.objects.get(object.index())?;
        self.materials.get(o.material.index())
    }

    /// The light an object emits as, if any.
    #[inline]
    pub fn emitter(&self, object: ShapeId) -> Option<(LightId, &Light)> {
        let id = self.objects.get(object.index())?.light?;
        Some((id, self.lights.get(id.index())?))
    }

    /// The shape a light emits from (area lights).
    #[inline]
    pub fn light_shape(&self, light: &Light) -> Option<&Shape> {
        match light {
            Light::Area { shape, .. } => self.shape(*shape),
            Light::Point { .. } => None,
        }
    }

    /// Shape `shape`.
    #[inline]
    pub fn shape(&self, shape: ShapeId) -> Option<&Shape> {
        self.objects.get(shape.index()).map(|o| &o.shape)
    }

    /// The nearest hit in `(t_min, t_max)`, ignoring object `skip`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32, skip: Option<ShapeId>) -> Option<Hit> {
        self.query(ray, t_min, t_max, Filter::AllBut(skip.map_or(usize::MAX, ShapeId::index)))
    }

    /// The nearest hit beyond `t_near` of the camera ray `ray` through pixel `(x, y)`: that of
    /// [`Scene::intersect`], bit for bit, with the tests of the objects no camera ray through
    /// the pixel's tile of the film can hit left out ([`CameraCull`]), in f32 and in fixed
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
    /// from [`CULLED`](crate::query::camera_cull::CULLED) on may always be hit).
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
    /// between the receiver and the light found ([`ShadowCull`]). For rays from elsewhere the
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
        let nearest = self
            .intersect_from(from, dir, 0.0, f32::INFINITY, Filter::AllBut(skip.index()))
            .map(|h| h.object);
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
    /// testing only the objects that may lie between the two ([`ShadowCull`]). For rays from
    /// elsewhere, or to other points, the answer may differ: use [`Scene::unoccluded`].
    #[inline]
    pub fn shadow_unoccluded(&self, ray: &Ray, t_max: f32, receiver: ShapeId, light: LightId) -> bool {
        let emitter = self.light(light).and_then(Light::shape);
        self.with_rays_from(ray.origin, |from| {
            self.unoccluded_from(from, ray.dir, t_max, receiver, emitter, Some(light))
        })
    }

    /// The objects that may block a shadow ray from a point of object `receiver` to light
    /// `light`: bit i for object i (objects from [`CULLED`](crate::query::camera_cull::CULLED) on, and
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Field;

    fn cam() -> CameraDesc {
        crate::geometry::test_desc(40.0)
    }

    #[test]
    fn capacities_are_errors_not_panics() {
        let mut s: Scene<1, 1, 1> = Scene::new(cam(), Film::new(4, 4).unwrap()).unwrap();
        let m = s.add_material(Material::lambertian(Rgb::ONE).unwrap()).unwrap();
        assert_eq!(
            s.add_material(Material::lambertian(Rgb::ONE).unwrap()),
            Err(SceneError::CapacityExceeded(Collection::Materials))
        );
        let sh = s.add_shape(Shape::sphere(Vec3::ZERO, 1.0).unwrap(), m).unwrap();
        assert_eq!(
            s.add_shape(Shape::sphere(Vec3::ZERO, 1.0).unwrap(), m),
            Err(SceneError::CapacityExceeded(Collection::Shapes))
        );
        assert_eq!(
            s.add_area_light(sh, Rgb::new(-1.0, 0.0, 0.0)),
            Err(SceneError::OutOfRange(Field::Radiance))
        );
        s.add_area_light(sh, Rgb::ONE).unwrap();
        assert_eq!(s.add_area_light(sh, Rgb::ONE), Err(SceneError::AlreadyEmitting));
        assert_eq!(
            s.add_point_light(Vec3::ONE, Rgb::ONE),
            Err(SceneError::CapacityExceeded(Collection::Lights))
        );
        assert_eq!(
            s.add_shape(Shape::sphere(Vec3::ZERO, 1.0).unwrap(), MaterialId::new(7)),
            Err(SceneError::UnknownMaterial)
        );
    }

    /// A scene of every kind of object: two quads (one a light), a sphere light, a point
    /// light, both materials.
    fn every_kind() -> Scene<4, 3, 2> {
        let mut s: Scene<4, 3, 2> = Scene::new(cam(), Film::new(16, 12).unwrap()).unwrap();
        let white = s.add_material(Material::lambertian(Rgb::splat(0.5)).unwrap()).unwrap();
        let glossy = s.add_material(Material::ggx_conductor(0.1, Rgb::ONE).unwrap()).unwrap();
        let floor =
            [Vec3::new(-2., 0., 2.), Vec3::new(2., 0., 2.), Vec3::new(2., 0., -2.), Vec3::new(-2., 0., -2.)];
        s.add_shape(Shape::quad(floor).unwrap(), glossy).unwrap();
        let panel =
            [Vec3::new(-1., 3., -1.), Vec3::new(-1., 3., 1.), Vec3::new(1., 3., 1.), Vec3::new(1., 3., -1.)];
        let p = s.add_shape(Shape::quad(panel).unwrap(), white).unwrap();
        s.add_area_light(p, Rgb::new(1.0, 2.0, 3.0)).unwrap();
        let ball = s.add_shape(Shape::sphere(Vec3::new(0.5, 1.0, 0.0), 0.25).unwrap(), white).unwrap();
        s.add_area_light(ball, Rgb::splat(4.0)).unwrap();
        s.add_point_light(Vec3::new(-1.0, 2.0, 1.0), Rgb::splat(5.0)).unwrap();
        s
    }

    fn image_of<const S: usize, const L: usize, const M: usize>(s: &Scene<S, L, M>) -> std::vec::Vec<u32> {
        let mut words = std::vec::Vec::new();
        s.write_image(&mut |w| words.push(w));
        words
    }

    #[test]
    fn an_image_loads_back_the_same_scene_into_any_capacity() {
        let built = every_kind();
        let words = image_of(&built);
        let mut loaded: Scene<9, 5, 7> = Scene::EMPTY;
        loaded.load_image(&words).unwrap();
        assert_eq!(loaded.objects(), built.objects());
        assert_eq!(loaded.materials(), built.materials());
        assert_eq!(loaded.lights(), built.lights());
        assert_eq!(loaded.camera(), built.camera());
        assert_eq!(loaded.film(), built.film());
        assert_eq!(loaded.camera_cull, built.camera_cull);
        assert_eq!(image_of(&loaded), words, "the loaded scene writes the same image");
        // Every query answers alike (camera rays through every pixel, their shadow pairs).
        for y in 0..12 {
            for x in 0..16 {
                let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let (ray, hit) = built.camera_hit(p, x, y);
                assert_eq!(loaded.camera_hit(p, x, y), (ray, hit));
                if let Some(h) = hit {
                    for l in 0..3 {
                        let (r, l) = (h.object, LightId::new(l));
                        assert_eq!(loaded.shadow_candidates(r, l), built.shadow_candidates(r, l));
                    }
                }
            }
        }
    }

    #[test]
    fn damaged_images_are_errors_and_leave_the_scene_empty() {
        let words = image_of(&every_kind());
        let mut s: Scene<4, 3, 2> = Scene::EMPTY;
        // Every truncation, every word changed to 0, 1 or all ones: an error or (a value changed)
        // a scene, never a panic.
        for n in 0..words.len() {
            assert_eq!(s.load_image(&words[..n]), Err(SceneError::BadImage), "truncated to {n}");
            assert!(s.objects().is_empty() && s.lights().is_empty());
        }
        for i in 0..words.len() {
            for v in [0, 1, u32::MAX] {
                let mut w = words.clone();
                w[i] = v;
                let _ = s.load_image(&w);
            }
        }
        // Too small a scene for the image.
        let mut small: Scene<2, 3, 2> = Scene::EMPTY;
        assert_eq!(small.load_image(&words), Err(SceneError::BadImage));
        let mut w = words.clone();
        w.push(0);
        assert_eq!(s.load_image(&w), Err(SceneError::BadImage), "trailing words");
    }
}
