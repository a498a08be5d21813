//! Plate x light regions of the Veach scene, derived from the scene geometry: every glossy quad
//! ("plate") and every sphere light whose mirror image in the plate's plane is seen inside the
//! plate from the camera gives a glint point on the plate. The pixels whose camera ray (through
//! the pixel centre) first hits a plate belong to the region of that plate's nearest glint, so
//! each plate is cut into one region per light. Error per region tells which technique fails
//! where: BSDF sampling on small lights over rough plates, light sampling on big lights over
//! smooth plates.
//!
//! A region's error is measured on the light of its own glint alone: each light is rendered
//! in a copy of the scene where every other emitter has zero radiance. Light selection keeps its
//! probabilities (uniform over all lights) and every camera sample draws the same random numbers,
//! so such a render is exactly the part of the full render that this light contributes; without
//! the isolation, rare hits of the small bright lights by BSDF samples would swamp every region.
//! Methods that choose lights otherwise than uniformly are left out (no region errors).

use picomis::{
    Light, LightSelection, Material, MaterialId, Ray, RenderSettings, Rgb, Scene, SceneError, ShapeId, Vec2,
    Vec3,
};
use picomis_host::HostScene;
use picomis_host::study::StudyMethod;
use rayon::prelude::*;

use super::measure::reflected;
use super::metrics::channel_errors;
use super::reference::{self, Reference};
use crate::SimError;
use crate::render::{progress_bar, render_estimates};
use crate::scenes::Loaded;

/// Relative MSE of one region in a render of its light alone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RegionRecord {
    /// Index in [`super::methods::methods`].
    pub method: usize,
    /// Seed.
    pub seed: u32,
    /// Index in [`RegionMap::regions`].
    pub region: usize,
    /// Relative MSE of the reflected light of the region's light, in the region.
    pub rel_mse: f64,
}

/// One plate x light region.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    /// Index into [`RegionMap::plates`].
    pub plate: usize,
    /// Index into [`RegionMap::lights`].
    pub light: usize,
    /// The glint: where the light's centre is mirrored in the plate, seen from the camera.
    pub glint: Vec3,
    /// Pixels in the region.
    pub pixels: usize,
}

/// The regions of a scene at the study film.
#[derive(Clone, Debug)]
pub struct RegionMap {
    /// Film width.
    pub width: u32,
    /// Film height.
    pub height: u32,
    /// GGX alpha of each plate, smoothest first.
    pub plates: Vec<f32>,
    /// Radius of each light, smallest first.
    pub lights: Vec<f32>,
    /// Index in the scene's light list of each light.
    pub light_ids: Vec<usize>,
    /// The regions, by plate then light.
    pub regions: Vec<Region>,
    /// The region of each pixel, if any.
    pub pixel: Vec<Option<u16>>,
}

impl RegionMap {
    /// The regions of `scene`, or `None` when it has fewer than two glossy quads or two sphere
    /// lights with glints.
    pub fn find<const S: usize, const L: usize, const M: usize>(scene: &Scene<S, L, M>) -> Option<Self> {
        let camera = scene.camera().desc().origin;
        let objects = scene.objects();
        // (object, alpha) of the plates; (object, centre, radius) of the sphere lights.
        let mut plates: Vec<(usize, f32)> = (0..objects.len())
            .filter_map(|i| match scene.material(ShapeId::new(i as u16)) {
                Some(Material::GgxConductor { alpha, .. })
                    if objects[i].shape.as_sphere().is_none()
                        && scene.emitter(ShapeId::new(i as u16)).is_none() =>
                {
                    Some((i, *alpha))
                }
                _ => None,
            })
            .collect();
        // (light index, centre, radius) of the sphere lights.
        let mut lights: Vec<(usize, Vec3, f32)> = scene
            .lights()
            .iter()
            .enumerate()
            .filter_map(|(li, l)| match l {
                Light::Area { shape, .. } => {
                    objects.get(shape.index())?.shape.as_sphere().map(|(c, r)| (li, c, r))
                }
                Light::Point { .. } => None,
            })
            .collect();
        plates.sort_by(|a, b| a.1.total_cmp(&b.1));
        lights.sort_by(|a, b| a.2.total_cmp(&b.2));

        let mut glints: Vec<(usize, usize, Vec3)> = Vec::new(); // (plate index, light index, point)
        for (pi, &(object, _)) in plates.iter().enumerate() {
            let shape = &objects[object].shape;
            let p0 = shape.centroid();
            let n = shape.normal_at(p0);
            if (camera - p0).dot(n) <= 0.0 {
                continue;
            }
            for (li, &(_, centre, _)) in lights.iter().enumerate() {
                let h = (centre - p0).dot(n);
                if h <= 0.0 {
                    continue;
                }
                let mirrored = centre - n * (2.0 * h);
                let d = mirrored - camera;
                let ray = Ray { origin: camera, dir: d.normalize() };
                if let Some(t) = shape.intersect(&ray, 0.0, d.length()) {
                    glints.push((pi, li, ray.at(t)));
                }
            }
        }
        // Keep the plates and lights that have glints, renumbered.
        let used_plates: Vec<usize> =
            (0..plates.len()).filter(|p| glints.iter().any(|g| g.0 == *p)).collect();
        let used_lights: Vec<usize> =
            (0..lights.len()).filter(|l| glints.iter().any(|g| g.1 == *l)).collect();
        if used_plates.len() < 2 || used_lights.len() < 2 {
            return None;
        }
        let mut regions: Vec<Region> = glints
            .iter()
            .map(|&(p, l, glint)| Region {
                plate: used_plates.iter().position(|&q| q == p).unwrap_or(0),
                light: used_lights.iter().position(|&q| q == l).unwrap_or(0),
                glint,
                pixels: 0,
            })
            .collect();
        regions.sort_by_key(|r| (r.plate, r.light));
        let plate_objects: Vec<usize> = used_plates.iter().map(|&p| plates[p].0).collect();

        let film = scene.film();
        let (w, h) = (film.width(), film.height());
        let mut pixel = vec![None; film.pixels() as usize];
        for y in 0..h {
            for x in 0..w {
                let uv = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                let (ray, t_near) = scene.camera().ray(uv);
                let Some(hit) = scene.intersect(&ray, t_near, f32::INFINITY, None) else { continue };
                let Some(plate) = plate_objects.iter().position(|&o| o == hit.object.index()) else {
                    continue;
                };
                let nearest = regions
                    .iter()
                    .enumerate()
                    .filter(|(_, r)| r.plate == plate)
                    .min_by(|a, b| {
                        (a.1.glint - hit.point.p).length().total_cmp(&(b.1.glint - hit.point.p).length())
                    })
                    .map(|(i, _)| i);
                if let Some(i) = nearest {
                    regions[i].pixels += 1;
                    pixel[(y * w + x) as usize] = u16::try_from(i).ok();
                }
            }
        }
        Some(Self {
            width: w,
            height: h,
            plates: used_plates.iter().map(|&p| plates[p].1).collect(),
            lights: used_lights.iter().map(|&l| lights[l].2).collect(),
            light_ids: used_lights.iter().map(|&l| lights[l].0).collect(),
            regions,
            pixel,
        })
    }

    /// Relative MSE of `image` against `reference` in each region (NaN for an empty region).
    pub fn rel_mse(&self, image: &[Rgb], reference: &[Rgb]) -> Vec<f64> {
        let mut sums = vec![0.0; self.regions.len()];
        for ((region, i), r) in self.pixel.iter().zip(image).zip(reference) {
            if let Some(k) = region {
                for (v, rv) in [(i.x, r.x), (i.y, r.y), (i.z, r.z)] {
                    sums[usize::from(*k)] += channel_errors(v, rv).1;
                }
            }
        }
        sums.iter().zip(&self.regions).map(|(s, r)| s / (3 * r.pixels) as f64).collect()
    }

    /// The region of plate `p` and light `l`, if it has a glint.
    pub fn index(&self, p: usize, l: usize) -> Option<usize> {
        self.regions.iter().position(|r| r.plate == p && r.light == l)
    }
}

/// A copy of `scene` in which only light `keep` (an index into its light list) emits; every
/// other light stays in the list with zero radiance or intensity, so light selection, light
/// indices and the random numbers each sample draws are those of `scene`.
pub fn isolate<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    keep: usize,
) -> Result<Scene<S, L, M>, SceneError> {
    let mut out = Scene::new(scene.camera().desc(), scene.film())?;
    let materials: Vec<MaterialId> =
        scene.materials().iter().map(|m| out.add_material(*m)).collect::<Result<_, _>>()?;
    let mut shapes: Vec<ShapeId> = Vec::new();
    for (i, o) in scene.objects().iter().enumerate() {
        // Materials are values: the first equal one is as good as the original.
        let m = scene
            .material(ShapeId::new(i as u16))
            .and_then(|m| scene.materials().iter().position(|x| x == m))
            .unwrap_or(0);
        let id = *materials.get(m).ok_or(SceneError::UnknownMaterial)?;
        shapes.push(out.add_shape(o.shape, id)?);
    }
    for (li, light) in scene.lights().iter().enumerate() {
        let on = li == keep;
        match *light {
            Light::Area { shape, radiance } => {
                let id = *shapes.get(shape.index()).ok_or(SceneError::UnknownMaterial)?;
                out.add_area_light(id, if on { radiance } else { Rgb::ZERO })?;
            }
            Light::Point { position, intensity } => {
                out.add_point_light(position, if on { intensity } else { Rgb::ZERO })?;
            }
        }
    }
    Ok(out)
}

/// What the region study measured: per-region errors and the reference of each light.
#[derive(Clone, Debug, Default)]
pub struct RegionStudy {
    /// One record per method, seed and region.
    pub records: Vec<RegionRecord>,
    /// The reference of each light alone (in the order of [`RegionMap::lights`]).
    pub references: Vec<Reference>,
    /// Samples per pixel of the region renders.
    pub spp: u32,
}

/// The render settings of a method (by index) at an spp with a seed.
pub type MethodSettings<'a> = &'a dyn Fn(usize, u32, u32) -> Result<RenderSettings, SimError>;

/// Renders each light of `map` alone with every method of `methods` that runs on the scene
/// (`methods.1`) at `spp` for each seed, with the method's settings (`methods.2`) and arithmetic
/// of the ray queries, and measures the error of its regions against that light's own reference
/// (`ref_spp` samples per pixel, `samples` light and BSDF samples).
#[allow(clippy::too_many_arguments)]
pub fn study(
    scene: &HostScene,
    map: &RegionMap,
    loaded: &Loaded,
    cache: &std::path::Path,
    ref_spp: u32,
    samples: (u16, u16),
    methods: (&[StudyMethod], &[bool], MethodSettings<'_>),
    spp: u32,
    seeds: &[u32],
) -> Result<RegionStudy, SimError> {
    let (methods, runs, settings) = methods;
    let mut out = RegionStudy { spp, ..RegionStudy::default() };
    let h = u64::from(scene.film().height());
    for (l, &light) in map.light_ids.iter().enumerate() {
        let alone =
            isolate(scene, light).map_err(|e| SimError::Usage(format!("isolating light {light}: {e}")))?;
        let variant = format!("-light{light}");
        let r = reference::get(&alone, loaded, cache, ref_spp, samples, &variant)?;
        let renders = methods.len() as u64 * seeds.len() as u64 * u64::from(spp);
        let name = format!("{}: light {} of {} alone", loaded.file.name(), l + 1, map.light_ids.len());
        let bar = progress_bar(renders * h, &name);
        for &seed in seeds {
            for (mi, m) in methods.iter().enumerate() {
                if m.extras.selection != LightSelection::Uniform || !runs.get(mi).copied().unwrap_or(false) {
                    // Isolating the light would change this method's selection probabilities,
                    // or the method's arithmetic cannot represent the scene.
                    bar.inc(u64::from(spp) * h);
                    continue;
                }
                let mut scene = alone.clone();
                m.extras.prepare(&mut scene).map_err(|e| SimError::Usage(format!("{}: {e}", m.label)))?;
                let img = render_estimates(&scene, &settings(mi, spp, seed)?, &bar)
                    .map_err(|e| SimError::Usage(format!("{}: {e}", m.label)))?
                    .pixels;
                let values: Vec<Rgb> = img.par_iter().map(reflected).collect();
                let errors = map.rel_mse(&values, &r.reflected);
                for (k, _) in map.regions.iter().enumerate().filter(|(_, g)| g.light == l) {
                    out.records.push(RegionRecord { method: mi, seed, region: k, rel_mse: errors[k] });
                }
            }
        }
        bar.finish_and_clear();
        out.references.push(r);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::load;

    #[test]
    fn the_veach_scene_has_four_plates_times_four_lights() {
        let loaded = load(Some("veach_mis")).unwrap();
        let film = picomis::Film::new(96, 64).unwrap();
        let map = RegionMap::find(&loaded.build(film).unwrap()).expect("regions");
        assert_eq!(map.plates, vec![0.005, 0.02, 0.05, 0.1]);
        assert_eq!(map.lights, vec![0.03333, 0.1, 0.3, 0.9]);
        assert_eq!(map.light_ids, vec![0, 1, 2, 3]);
        assert_eq!(map.regions.len(), 16);
        assert!(map.regions.iter().all(|r| r.pixels > 20), "{:?}", map.regions);
        // Along each plate, the glints go left to right from the small light to the big one.
        for p in 0..4 {
            let xs: Vec<f32> = (0..4).map(|l| map.regions[map.index(p, l).unwrap()].glint.x).collect();
            assert!(xs.windows(2).all(|w| w[0] < w[1]), "{xs:?}");
        }
        // Error per region: zero against itself, and only where the image differs.
        let reference = vec![Rgb::splat(0.5); 96 * 64];
        assert!(map.rel_mse(&reference, &reference).iter().all(|&e| e == 0.0));
        let mut image = reference.clone();
        let first = map.pixel.iter().position(|p| *p == Some(0)).unwrap();
        image[first] = Rgb::splat(1.5);
        let e = map.rel_mse(&image, &reference);
        assert!(e[0] > 0.0 && e[1..].iter().all(|&v| v == 0.0));
    }

    #[test]
    fn lights_rendered_alone_add_up_to_the_full_render() {
        // Same random numbers per sample: the parts are the full render's, up to f32 rounding.
        let loaded = load(Some("veach_mis")).unwrap();
        let scene = loaded.build(picomis::Film::new(48, 32).unwrap()).unwrap();
        let settings = picomis::RenderSettings::new(
            picomis::Method::Mis(picomis::Heuristic::Power { beta: 2.0 }),
            1,
            1,
            2,
            3,
        )
        .unwrap()
        // (Selection by contribution would choose by the lights' strengths: other choices.)
        .with_light_selection(picomis::LightSelection::Uniform);
        let film = scene.film();
        let px = |s: &HostScene| -> Vec<Rgb> {
            let r = picomis_host::renderer(s, &settings).unwrap();
            (0..film.pixels())
                .map(|i| r.render_pixel(i % film.width(), i / film.width()).radiance())
                .collect()
        };
        let full = px(&scene);
        let mut sum = vec![Rgb::ZERO; full.len()];
        for l in 0..scene.lights().len() {
            let alone = isolate(&scene, l).unwrap();
            assert_eq!(alone.lights().len(), scene.lights().len());
            for (a, b) in sum.iter_mut().zip(px(&alone)) {
                *a += b;
            }
        }
        assert_eq!(scene.lights().len(), 5);
        for (f, s) in full.iter().zip(&sum) {
            assert!((*f - *s).abs().max_element() <= 1e-4 * f.max_element().max(1.0), "{f} vs {s}");
        }
        assert!(full.iter().map(|c| c.x).sum::<f32>() > 0.0);
    }

    #[test]
    fn scenes_without_plates_have_no_regions() {
        let loaded = load(Some("lambert_sphere")).unwrap();
        assert!(RegionMap::find(&loaded.build(loaded.file.film()).unwrap()).is_none());
    }
}
