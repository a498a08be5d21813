//! A scene in fixed-capacity storage: `S` shapes, `L` lights, `M` materials, chosen by the user
//! of the kernel (a firmware build uses exactly its scene's counts). Every value is validated as
//! it is added; a full collection is an error, never a panic.

use heapless::Vec;

use crate::accel::{self, Filter, Packets};
use crate::camera::{Camera, CameraDesc, Film};
use crate::error::{Collection, Field, SceneError};
use crate::light::{Light, LightSample, LightSelection, SphereSampling};
use crate::material::Material;
use crate::math::{Rgb, Vec2, Vec3, finite3};
use crate::sampling::{DiscreteSample, discrete_pdf, sample_discrete, sample_uniform_index};
use crate::shape::{Ray, Shape, SurfacePoint};

/// Index of a material in its scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MaterialId(u16);

/// Index of a shape in its scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ShapeId(u16);

/// Index of a light in its scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LightId(u16);

impl ShapeId {
    /// The index.
    pub fn index(self) -> usize {
        usize::from(self.0)
    }
}

impl LightId {
    /// The index.
    pub fn index(self) -> usize {
        usize::from(self.0)
    }
}

/// A shape with its material and, if it emits, its light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Object {
    /// Geometry.
    pub shape: Shape,
    material: u16,
    light: Option<u16>,
}

/// The first surface a ray meets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the ray.
    pub t: f32,
    /// Index of the object hit.
    pub object: usize,
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
    total_power: f32,
}

fn check_emission(c: Rgb, field: Field) -> Result<(), SceneError> {
    if !finite3(c) {
        return Err(SceneError::NonFinite(field));
    }
    if c.min_element() < 0.0 {
        return Err(SceneError::OutOfRange(field));
    }
    Ok(())
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
            total_power: 0.0,
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
        Ok(MaterialId(id))
    }

    /// Adds a shape that reflects with `material`.
    pub fn add_shape(&mut self, shape: Shape, material: MaterialId) -> Result<ShapeId, SceneError> {
        if usize::from(material.0) >= self.materials.len() {
            return Err(SceneError::UnknownMaterial);
        }
        let id = index16(self.objects.len(), Collection::Shapes)?;
        self.objects
            .push(Object { shape, material: material.0, light: None })
            .map_err(|_| SceneError::CapacityExceeded(Collection::Shapes))?;
        self.packets.push(usize::from(id), &shape);
        Ok(ShapeId(id))
    }

    /// Makes shape `shape` an area emitter of constant `radiance` on its front side.
    pub fn add_area_light(&mut self, shape: ShapeId, radiance: Rgb) -> Result<LightId, SceneError> {
        check_emission(radiance, Field::Radiance)?;
        let object = self.objects.get(shape.index()).ok_or(SceneError::UnknownShape)?;
        if object.light.is_some() {
            return Err(SceneError::AlreadyEmitting);
        }
        let light = Light::Area { shape: shape.0, radiance };
        let power = light.power(Some(&object.shape));
        let id = self.push_light(light, power)?;
        if let Some(object) = self.objects.get_mut(shape.index()) {
            object.light = Some(id.0);
        }
        self.packets.set_emitter(shape.index());
        Ok(id)
    }

    /// Adds a point light of radiant `intensity` at `position`.
    pub fn add_point_light(&mut self, position: Vec3, intensity: Rgb) -> Result<LightId, SceneError> {
        if !finite3(position) {
            return Err(SceneError::NonFinite(Field::Position));
        }
        check_emission(intensity, Field::Intensity)?;
        let light = Light::Point { position, intensity };
        self.push_light(light, light.power(None))
    }

    fn push_light(&mut self, light: Light, power: f32) -> Result<LightId, SceneError> {
        let id = index16(self.lights.len(), Collection::Lights)?;
        let full = SceneError::CapacityExceeded(Collection::Lights);
        self.lights.push(light).map_err(|_| full)?;
        self.light_power.push(power).map_err(|_| full)?;
        self.total_power = self.light_power.iter().sum();
        Ok(LightId(id))
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

    /// The material of object `object`.
    #[inline]
    pub fn material(&self, object: usize) -> Option<&Material> {
        let o = self.objects.get(object)?;
        self.materials.get(usize::from(o.material))
    }

    /// The light an object emits as, if any.
    #[inline]
    pub fn emitter(&self, object: usize) -> Option<(usize, &Light)> {
        let i = usize::from(self.objects.get(object)?.light?);
        Some((i, self.lights.get(i)?))
    }

    /// The shape a light emits from (area lights).
    #[inline]
    pub fn light_shape(&self, light: &Light) -> Option<&Shape> {
        match light {
            Light::Area { shape, .. } => self.objects.get(usize::from(*shape)).map(|o| &o.shape),
            Light::Point { .. } => None,
        }
    }

    /// The nearest hit in `(t_min, t_max)`, ignoring object `skip`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32, skip: Option<usize>) -> Option<Hit> {
        let skip = skip.unwrap_or(usize::MAX);
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
        Some(Hit { t, object, point: SurfacePoint { p, n }, front: n.dot(ray.dir) < 0.0 })
    }

    /// The first surface along `ray` (ignoring object `skip`) if it is an emitter's front side:
    /// the emitting hit, its light index and radiance. Cheaper than [`Scene::intersect`]: the
    /// closest emitter is found first, then only an any-hit occlusion test by the other objects
    /// runs up to it, so rays that miss every light test only the emitters.
    #[inline]
    pub fn emitter_hit(&self, ray: &Ray, skip: usize) -> Option<(Hit, usize, Rgb)> {
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
        let light_index = usize::from(self.objects.get(best)?.light?);
        match self.lights.get(light_index)? {
            Light::Area { radiance, .. } => Some((hit, light_index, *radiance)),
            Light::Point { .. } => None,
        }
    }

    /// True when nothing but objects `a` and `b` lies on the ray before `t_max`.
    #[inline]
    pub fn unoccluded(&self, ray: &Ray, t_max: f32, a: usize, b: Option<usize>) -> bool {
        let b = b.unwrap_or(usize::MAX);
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

    /// Chooses a light for a light sample: its index and selection probability.
    #[inline]
    pub fn select_light(&self, u: f32, selection: LightSelection) -> Option<(usize, f32)> {
        self.choose_light(u, selection).map(|d| (d.index, d.prob))
    }

    /// [`Scene::select_light`], also returning `u` rescaled within the chosen light's interval.
    #[inline]
    pub fn choose_light(&self, u: f32, selection: LightSelection) -> Option<DiscreteSample> {
        if let LightSelection::Power = selection {
            if let Some(pick) = sample_discrete(&self.light_power, self.total_power, u) {
                return Some(pick);
            }
        }
        // Uniform (also when no light has power).
        sample_uniform_index(self.lights.len(), u)
    }

    /// Probability that [`Scene::select_light`] picks light `i`.
    #[inline]
    pub fn light_selection_pdf(&self, i: usize, selection: LightSelection) -> f32 {
        let n = self.lights.len();
        if i >= n {
            return 0.0;
        }
        match selection {
            LightSelection::Power if self.total_power > 0.0 && self.total_power.is_finite() => {
                discrete_pdf(&self.light_power, self.total_power, i)
            }
            _ => 1.0 / n as f32,
        }
    }

    /// Light sampling from `x` with one 2-D random point: `u.x` chooses a light and, rescaled
    /// within that light's interval, goes on with `u.y` to choose the point on it (as Mitsuba
    /// does), so a stratified `u` stays stratified for every light. The returned pdf includes the
    /// selection probability. Also returns the light's emitting object, if any.
    #[inline]
    pub fn sample_light(
        &self,
        x: Vec3,
        u: Vec2,
        spheres: SphereSampling,
        selection: LightSelection,
    ) -> Option<(LightSample, Option<usize>)> {
        let DiscreteSample { index: i, prob: p_select, u_remapped } = self.choose_light(u.x, selection)?;
        let light = self.lights.get(i)?;
        let sample = light.sample_li(self.light_shape(light), x, Vec2::new(u_remapped, u.y), spheres)?;
        let object = match light {
            Light::Area { shape, .. } => Some(usize::from(*shape)),
            Light::Point { .. } => None,
        };
        Some((LightSample { pdf: sample.pdf * p_select, ..sample }, object))
    }

    /// Pdf (solid angle at `x`, selection included) with which light sampling produces the
    /// direction to point `y` on light `i`.
    #[inline]
    pub fn light_pdf(
        &self,
        i: usize,
        x: Vec3,
        y: &SurfacePoint,
        spheres: SphereSampling,
        selection: LightSelection,
    ) -> f32 {
        let Some(light) = self.lights.get(i) else { return 0.0 };
        self.light_selection_pdf(i, selection) * light.pdf_li(self.light_shape(light), x, y, spheres)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::FovAxis;

    fn cam() -> CameraDesc {
        CameraDesc {
            origin: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_deg: 40.0,
            fov_axis: FovAxis::Y,
            near_clip: 0.0,
        }
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
            s.add_shape(Shape::sphere(Vec3::ZERO, 1.0).unwrap(), MaterialId(7)),
            Err(SceneError::UnknownMaterial)
        );
    }

    #[test]
    fn selection_probabilities_sum_to_one() {
        let mut s: Scene<2, 3, 1> = Scene::new(cam(), Film::new(4, 4).unwrap()).unwrap();
        let m = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
        let a = s.add_shape(Shape::sphere(Vec3::ZERO, 1.0).unwrap(), m).unwrap();
        s.add_area_light(a, Rgb::splat(2.0)).unwrap();
        s.add_point_light(Vec3::ONE, Rgb::splat(1.0)).unwrap();
        s.add_point_light(Vec3::ONE, Rgb::ZERO).unwrap();
        for sel in [LightSelection::Uniform, LightSelection::Power] {
            let sum: f32 = (0..3).map(|i| s.light_selection_pdf(i, sel)).sum();
            assert!((sum - 1.0).abs() < 1e-6);
            // Never selects a light with zero selection probability.
            for k in 0..1000 {
                let (i, p) = s.select_light(k as f32 / 1000.0, sel).unwrap();
                assert!(p > 0.0 && (p - s.light_selection_pdf(i, sel)).abs() < 1e-6);
            }
        }
    }
}
