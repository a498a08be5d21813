//! A scene in fixed-capacity storage: `S` shapes, `L` lights, `M` materials, chosen by the user
//! of the kernel (a firmware build uses exactly its scene's counts). Every value is validated as
//! it is added; a full collection is an error, never a panic. The scene builds and answers ray
//! queries; choosing and sampling lights is the light sampler's job (`light/`).

mod ids;
mod image;
mod light;
mod material;
mod rays;

pub use ids::{LightId, MaterialId, ShapeId};
pub use light::{Emission, Light, MAX_EMISSION};
pub use material::{BsdfSample, Material, Outgoing};

use heapless::Vec;

use crate::error::{Collection, SceneError};
use crate::geometry::{Camera, CameraDesc, Film};
use crate::geometry::{Shape, SurfacePoint};
use crate::num::{Rgb, Vec3};
#[cfg(feature = "fixed")]
use crate::query::Arith;
use crate::query::accel::{CameraRays, Packets, Target};
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
    #[cfg_attr(docsrs, doc(cfg(feature = "fixed")))]
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
    #[cfg_attr(docsrs, doc(cfg(feature = "fixed")))]
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
    #[cfg_attr(docsrs, doc(cfg(feature = "fixed")))]
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
}
