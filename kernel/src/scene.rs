//! A scene in fixed-capacity storage: `S` shapes, `L` lights, `M` materials, chosen by the user
//! of the kernel (a firmware build uses exactly its scene's counts). Every value is validated as
//! it is added; a full collection is an error, never a panic. The scene builds and answers ray
//! queries; choosing and sampling lights is the light sampler's job
//! ([`LightSampler`](crate::light_sampler::LightSampler)).

use heapless::Vec;

use crate::accel::{self, Filter, Packets};
use crate::camera::{Camera, CameraDesc, Film};
use crate::error::{Collection, SceneError};
use crate::ids::{LightId, MaterialId, ShapeId};
use crate::light::Light;
use crate::material::Material;
use crate::math::{Rgb, Vec3};
use crate::sampling::GridDistribution;
use crate::shape::{Ray, Shape, SurfacePoint};

/// A shape with its material and, if it emits, its light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Object {
    /// Geometry.
    pub shape: Shape,
    material: MaterialId,
    light: Option<LightId>,
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
    /// The shapes again, four to a packet, for ray queries (hosted targets only).
    packets: Packets<S>,
    materials: Vec<Material, M>,
    lights: Vec<Light, L>,
    light_power: Vec<f32, L>,
    power_selection: GridDistribution<L>,
}

fn index16(len: usize, what: Collection) -> Result<u16, SceneError> {
    u16::try_from(len).map_err(|_| SceneError::CapacityExceeded(what))
}

impl<const S: usize, const L: usize, const M: usize> Scene<S, L, M> {
    /// An empty scene seen by `camera` on `film`.
    pub fn new(camera: CameraDesc, film: Film) -> Result<Self, SceneError> {
        Ok(Self {
            camera: Camera::new(camera, film)?,
            film,
            objects: Vec::new(),
            packets: Packets::default(),
            materials: Vec::new(),
            lights: Vec::new(),
            light_power: Vec::new(),
            power_selection: GridDistribution::default(),
        })
    }

    /// Changes the film resolution (the camera keeps its field of view).
    pub fn set_film(&mut self, film: Film) -> Result<(), SceneError> {
        self.camera = Camera::new(self.camera.desc(), film)?;
        self.film = film;
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
        self.objects
            .push(Object { shape, material, light: None })
            .map_err(|_| SceneError::CapacityExceeded(Collection::Shapes))?;
        self.packets.push(usize::from(id), &shape);
        Ok(ShapeId::new(id))
    }

    /// Makes shape `shape` an area emitter of constant `radiance` on its front side.
    pub fn add_area_light(&mut self, shape: ShapeId, radiance: Rgb) -> Result<LightId, SceneError> {
        let light = Light::area(shape, radiance)?;
        let object = self.objects.get(shape.index()).ok_or(SceneError::UnknownShape)?;
        if object.light.is_some() {
            return Err(SceneError::AlreadyEmitting);
        }
        let power = light.power(Some(&object.shape));
        let id = self.push_light(light, power)?;
        if let Some(object) = self.objects.get_mut(shape.index()) {
            object.light = Some(id);
        }
        self.packets.set_emitter(shape.index());
        Ok(id)
    }

    /// Adds a point light of radiant `intensity` at `position`.
    pub fn add_point_light(&mut self, position: Vec3, intensity: Rgb) -> Result<LightId, SceneError> {
        let light = Light::point(position, intensity)?;
        self.push_light(light, light.power(None))
    }

    fn push_light(&mut self, light: Light, power: f32) -> Result<LightId, SceneError> {
        let id = index16(self.lights.len(), Collection::Lights)?;
        let full = SceneError::CapacityExceeded(Collection::Lights);
        self.lights.push(light).map_err(|_| full)?;
        self.light_power.push(power).map_err(|_| full)?;
        self.power_selection = GridDistribution::new(&self.light_power);
        Ok(LightId::new(id))
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

    /// Each light's share of the emitted power, as light selection by power draws it.
    #[inline]
    pub fn light_powers(&self) -> &GridDistribution<L> {
        &self.power_selection
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
            Light::Area { shape, .. } => self.objects.get(shape.index()).map(|o| &o.shape),
            Light::Point { .. } => None,
        }
    }

    /// The nearest hit in `(t_min, t_max)`, ignoring object `skip`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32, skip: Option<ShapeId>) -> Option<Hit> {
        let skip = skip.map_or(usize::MAX, ShapeId::index);
        if accel::ENABLED {
            let (t, i) = self.packets.nearest(ray, t_min, t_max, Filter::AllBut(skip), |i| self.shape(i))?;
            return self.hit(ray, t, i);
        }
        let (mut t_far, mut best) = (t_max, usize::MAX);
        for (i, o) in self.objects.iter().enumerate() {
            if i != skip {
                if let Some(t) = o.shape.intersect(ray, t_min, t_far) {
                    t_far = t;
                    best = i;
                }
            }
        }
        self.hit(ray, t_far, best)
    }

    /// The shape of object `object`.
    #[inline]
    fn shape(&self, object: usize) -> Option<&Shape> {
        self.objects.get(object).map(|o| &o.shape)
    }

    /// The [`Hit`] record for object `object` at distance `t` along `ray`.
    #[inline]
    fn hit(&self, ray: &Ray, t: f32, object: usize) -> Option<Hit> {
        let shape = &self.objects.get(object)?.shape;
        let p = ray.at(t);
        let n = shape.normal_at(p);
        let object = ShapeId::new(object as u16); // < S, and S shapes have u16 indices
        Some(Hit { t, object, point: SurfacePoint { p, n }, front: n.dot(ray.dir) < 0.0 })
    }

    /// The first surface along `ray` (ignoring object `skip`) if it is an emitter's front side:
    /// the emitting hit, its light and radiance. Cheaper than [`Scene::intersect`]: the
    /// closest emitter is found first, then only an any-hit occlusion test by the other objects
    /// runs up to it, so rays that miss every light test only the emitters.
    #[inline]
    pub fn emitter_hit(&self, ray: &Ray, skip: ShapeId) -> Option<(Hit, LightId, Rgb)> {
        let skip = skip.index();
        let (mut t_far, mut best) = (f32::INFINITY, usize::MAX);
        if accel::ENABLED {
            let shape = |i| self.shape(i);
            (t_far, best) = self.packets.nearest(ray, 0.0, t_far, Filter::EmittersBut(skip), shape)?;
        } else {
            for (i, o) in self.objects.iter().enumerate() {
                if o.light.is_some() && i != skip {
                    if let Some(t) = o.shape.intersect(ray, 0.0, t_far) {
                        t_far = t;
                        best = i;
                    }
                }
            }
        }
        let hit = self.hit(ray, t_far, best)?;
        if !hit.front {
            return None; // the back of an emitter: it emits nothing this way
        }
        // Anything else in front of it? (Emitters were already compared above.)
        if accel::ENABLED {
            if self.packets.any(ray, 0.0, t_far, Filter::OthersBut(skip), |i| self.shape(i)) {
                return None;
            }
        } else {
            for (i, o) in self.objects.iter().enumerate() {
                if o.light.is_none() && i != skip && o.shape.intersect(ray, 0.0, t_far).is_some() {
                    return None;
                }
            }
        }
        let light = self.objects.get(best)?.light?;
        match self.lights.get(light.index())? {
            Light::Area { radiance, .. } => Some((hit, light, *radiance)),
            Light::Point { .. } => None,
        }
    }

    /// Calls `f` for every emitter whose front side `ray` meets (ignoring object `skip`), with the
    /// hit, the light, its radiance, and whether it is the first surface on the ray (visible).
    /// For the control variate, which needs the lights behind occluders too.
    #[inline]
    pub fn emitters_along(&self, ray: &Ray, skip: ShapeId, mut f: impl FnMut(Hit, LightId, Rgb, bool)) {
        let nearest = self.intersect(ray, 0.0, f32::INFINITY, Some(skip)).map(|h| h.object);
        for (i, o) in self.objects.iter().enumerate() {
            let Some(light) = o.light else { continue };
            if i == skip.index() {
                continue;
            }
            let Some(t) = o.shape.intersect(ray, 0.0, f32::INFINITY) else { continue };
            let Some(hit) = self.hit(ray, t, i).filter(|h| h.front) else { continue };
            if let Some(Light::Area { radiance, .. }) = self.lights.get(light.index()) {
                f(hit, light, *radiance, nearest == Some(hit.object));
            }
        }
    }

    /// True when nothing but objects `a` and `b` lies on the ray before `t_max`.
    #[inline]
    pub fn unoccluded(&self, ray: &Ray, t_max: f32, a: ShapeId, b: Option<ShapeId>) -> bool {
        let (a, b) = (a.index(), b.map_or(usize::MAX, ShapeId::index));
        if accel::ENABLED {
            return !self.packets.any(ray, 0.0, t_max, Filter::AllButTwo(a, b), |i| self.shape(i));
        }
        for (i, o) in self.objects.iter().enumerate() {
            if i != a && i != b && o.shape.intersect(ray, 0.0, t_max).is_some() {
                return false;
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Field;

    fn cam() -> CameraDesc {
        crate::camera::test_desc(40.0)
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
}
