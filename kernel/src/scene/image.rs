//! The scene as an image of 32-bit words (the `words` module): written on the host, loaded in
//! place on a device.

use crate::error::SceneError;
use crate::geometry::{Camera, Film, Shape};
use crate::query::accel::CameraRays;
use crate::query::camera_cull::CameraCull;
use crate::scene::{Light, LightId, Material, MaterialId, Object, Scene, ShapeId};
use crate::words::{Image, Words};

/// The first word of a scene image ([`Scene::write_image`]): "PMI" and the version of the image
/// format, 1.
const IMAGE_MAGIC: u32 = u32::from_be_bytes(*b"PMI\x01");

impl<const S: usize, const L: usize, const M: usize> Scene<S, L, M> {
    /// Writes the built scene to `out` as 32-bit words (the `words` module): its materials,
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
    /// queries run in f32 (`Scene::enable_arith` after loading for fixed point).
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::CameraDesc;
    use crate::num::{Rgb, Vec2, Vec3};

    fn cam() -> CameraDesc {
        crate::geometry::test_desc(40.0)
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
