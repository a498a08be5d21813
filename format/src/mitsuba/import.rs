//! Mitsuba 3 XML to `picomis-scene/1`: the subset picomis models (docs/simulator.md, "Mitsuba 3
//! scenes in and out"). Everything else is an error naming the element and its line; nothing is dropped
//! silently. Values are validated with the kernel's own constructors as they are read, so an
//! error points at the XML element that caused it.

use std::collections::{BTreeMap, HashMap};

use picomis::{CameraDesc, Film, FovAxis, Heuristic, Material, Method, RenderSettings, Shape, Vec3};
use roxmltree::{Node, ParsingOptions};

use super::SHAPE_ID_SUFFIX;
use super::json::{CameraOut, EmitterOut, FileOut, FilmOut, IntegratorOut, MaterialOut, PointOut, ShapeOut};
use super::transform::{Affine, cross, dot};
use super::xml::{Op, PARAM_TAGS, Reader};
use crate::{LoadError, check_camera};

/// Largest number of XML nodes read (scenes are small; this bounds work on hostile input).
const MAX_NODES: u32 = 200_000;

/// The BSDFs picomis models, for error messages.
const BSDFS: &str = "diffuse, roughconductor";

/// Converts Mitsuba 3 XML `text` (read from `file`, named in errors) into the text of a
/// `picomis-scene/1` file whose scene is called `name`.
pub(crate) fn import(text: &str, file: &str, name: &str) -> Result<String, LoadError> {
    let options = ParsingOptions { allow_dtd: false, nodes_limit: MAX_NODES, ..ParsingOptions::default() };
    let doc = roxmltree::Document::parse_with_options(text, options).map_err(|e| {
        let pos = e.pos();
        LoadError { file: format!("{file}:{}", pos.row), entry: "xml".into(), reason: e.to_string() }
    })?;
    let mut r = Reader { file, doc: &doc, defaults: HashMap::new() };
    let root = doc.root_element();
    if root.tag_name().name() != "scene" {
        return Err(r.error(root, "the root element must be <scene>"));
    }
    let version = r.need(root, "version")?;
    if !(version.starts_with("3.") || version.starts_with("2.")) {
        return Err(
            r.error(root, format!("version {version:?}: only Mitsuba 2 and 3 scenes (\"3.0.0\") are read"))
        );
    }
    let elements: Vec<Node> = root.children().filter(|c| c.is_element()).collect();
    for &e in &elements {
        if e.tag_name().name() == "default" {
            let key = e.attribute("name").ok_or_else(|| r.error(e, "missing attribute `name`"))?;
            let value = e.attribute("value").ok_or_else(|| r.error(e, "missing attribute `value`"))?;
            r.defaults.insert(key.to_string(), value.to_string());
        }
    }
    let r = r;

    let mut sensor = None;
    let mut integrator = None;
    let mut materials = Materials::default();
    // Named BSDFs first, so shapes may refer to them wherever they are declared.
    for &e in &elements {
        if e.tag_name().name() == "bsdf" {
            let id = r.need(e, "id").map_err(|_| r.error(e, "a top-level <bsdf> needs an `id`"))?;
            let m = bsdf(&r, e)?;
            if materials.by_id.insert(id.clone(), m).is_some() {
                return Err(r.error(e, format!("duplicate id {id:?}")));
            }
        }
    }
    // Every named BSDF is a material under its id (inline ones get other names).
    materials.named = materials.by_id.clone();
    let mut shapes = Vec::new();
    let mut lights = Vec::new();
    for &e in &elements {
        match e.tag_name().name() {
            "default" | "bsdf" => {}
            "integrator" => {
                if integrator.is_some() {
                    return Err(r.error(e, "a second <integrator>"));
                }
                integrator = Some(read_integrator(&r, e)?);
            }
            "sensor" => {
                if sensor.is_some() {
                    return Err(r.error(e, "a second <sensor> (picomis renders one camera)"));
                }
                sensor = Some(read_sensor(&r, e)?);
            }
            "shape" => shapes.push(read_shape(&r, e, &mut materials)?),
            "emitter" => lights.push(read_point(&r, e)?),
            _ => {
                return Err(r.error(
                    e,
                    "not modelled by picomis (default, integrator, sensor, bsdf, shape, emitter)",
                ));
            }
        }
    }
    let (camera, film) = sensor.ok_or_else(|| r.error(root, "no <sensor type=\"perspective\">"))?;
    let integrator = integrator.ok_or_else(|| {
        r.error(
            root,
            "no <integrator type=\"direct\"> (Mitsuba would use path tracing, which picomis does not model)",
        )
    })?;
    let out = FileOut {
        format: "picomis-scene/1",
        name: name.to_string(),
        description: "Imported from Mitsuba 3 XML by picomis-sim import.".into(),
        source: String::new(),
        film,
        camera,
        integrator,
        materials: materials.named,
        shapes,
        lights,
    };
    Ok(out.to_text())
}

/// Materials: named (top-level, by `id`) and all materials of the output by their JSON name.
#[derive(Default)]
struct Materials {
    by_id: BTreeMap<String, MaterialOut>,
    named: BTreeMap<String, MaterialOut>,
}

impl Materials {
    /// Adds `m` under `name` (or a variant of it if taken by a different material); returns the name.
    fn add(&mut self, name: &str, m: MaterialOut) -> String {
        let mut candidate = name.to_string();
        let mut k = 2;
        while self.named.contains_key(&candidate) {
            candidate = format!("{name}_{k}");
            k += 1;
        }
        self.named.insert(candidate.clone(), m);
        candidate
    }
}

/// The parameters and nested objects of one object element, taken as they are understood;
/// whatever is left is an error.
struct Obj<'a, 'input> {
    node: Node<'a, 'input>,
    params: Vec<(String, Node<'a, 'input>)>,
    objects: Vec<Node<'a, 'input>>,
}

impl<'a, 'input> Obj<'a, 'input> {
    fn new(r: &Reader, node: Node<'a, 'input>) -> Result<Self, LoadError> {
        let mut params: Vec<(String, Node)> = Vec::new();
        let mut objects = Vec::new();
        for c in node.children().filter(|c| c.is_element()) {
            if PARAM_TAGS.contains(&c.tag_name().name()) {
                let name = r.need(c, "name")?;
                if params.iter().any(|(n, _)| *n == name) {
                    return Err(r.error(c, format!("parameter {name:?} given twice")));
                }
                params.push((name, c));
            } else {
                objects.push(c);
            }
        }
        Ok(Obj { node, params, objects })
    }

    fn take(&mut self, name: &str) -> Option<Node<'a, 'input>> {
        let i = self.params.iter().position(|(n, _)| n == name)?;
        Some(self.params.remove(i).1)
    }

    /// Nested objects with tag `tag` (at most one).
    fn take_object(&mut self, r: &Reader, tag: &str) -> Result<Option<Node<'a, 'input>>, LoadError> {
        let mut found = None;
        let mut i = 0;
        while i < self.objects.len() {
            if self.objects[i].tag_name().name() == tag {
                let n = self.objects.remove(i);
                if found.is_some() {
                    return Err(r.error(n, format!("a second <{tag}> here")));
                }
                found = Some(n);
            } else {
                i += 1;
            }
        }
        Ok(found)
    }

    /// Errors on anything not taken: `known` lists what this object understands.
    fn finish(self, r: &Reader, known: &str) -> Result<(), LoadError> {
        let what = super::xml::describe(self.node);
        if let Some((_, p)) = self.params.first() {
            return Err(r.error(*p, format!("parameter not modelled by picomis for {what} ({known})")));
        }
        if let Some(o) = self.objects.first() {
            return Err(r.error(*o, format!("not modelled by picomis inside {what}")));
        }
        Ok(())
    }
}

fn kind(r: &Reader, node: Node) -> Result<String, LoadError> {
    r.need(node, "type")
}

fn v3(a: [f32; 3]) -> Vec3 {
    Vec3::from_array(a)
}

fn read_integrator(r: &Reader, node: Node) -> Result<IntegratorOut, LoadError> {
    if kind(r, node)? != "direct" {
        return Err(r.error(node, "not modelled by picomis (direct)"));
    }
    let mut o = Obj::new(r, node)?;
    let max = u32::from(u16::MAX);
    let shading = o.take("shading_samples").map(|p| r.count(p, max)).transpose()?.unwrap_or(1);
    let mut samples = [shading; 2];
    for (s, key) in samples.iter_mut().zip(["emitter_samples", "bsdf_samples"]) {
        if let Some(p) = o.take(key) {
            *s = r.count(p, max)?;
        }
    }
    if let Some(p) = o.take("hide_emitters") {
        if r.boolean(p)? {
            return Err(r.error(p, "hiding emitters is not modelled by picomis (use false)"));
        }
    }
    o.finish(r, "emitter_samples, bsdf_samples, shading_samples, hide_emitters")?;
    // u16 by the range check above.
    let [n_light, n_bsdf] = samples.map(|s| s as u16);
    // Mitsuba's direct integrator weights its samples with the power heuristic, beta 2.
    RenderSettings::new(Method::Mis(Heuristic::Power { beta: 2.0 }), n_light, n_bsdf, 1, 0)
        .map_err(|e| r.error(node, e.to_string()))?;
    Ok(IntegratorOut {
        kind: "direct",
        emitter_samples: n_light,
        bsdf_samples: n_bsdf,
        hide_emitters: false,
        mis: "power",
    })
}

fn read_sensor(r: &Reader, node: Node) -> Result<(CameraOut, FilmOut), LoadError> {
    if kind(r, node)? != "perspective" {
        return Err(r.error(node, "not modelled by picomis (perspective)"));
    }
    let mut o = Obj::new(r, node)?;
    let fov = o
        .take("fov")
        .ok_or_else(|| r.error(node, "missing <float name=\"fov\"> (focal_length is not modelled)"))?;
    let fov_deg = r.float(fov)?;
    let near_clip = o.take("near_clip").map(|p| r.float(p)).transpose()?.unwrap_or(0.01);
    if let Some(p) = o.take("far_clip") {
        if r.float(p)? < 1000.0 {
            return Err(r.error(p, "far_clip below 1000 is not modelled (picomis has no far plane)"));
        }
    }
    let axis = match o.take("fov_axis") {
        Some(p) => Some((p, r.string(p)?)),
        None => None,
    };
    let (origin, target, up) = match o.take("to_world") {
        None => ([0.0; 3], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
        Some(t) => match r.transform(t)?.as_slice() {
            [Op::LookAt { origin, target, up }] => (*origin, *target, *up),
            _ => {
                return Err(r.error(t, "a sensor's to_world must be one <lookat> (nothing else is modelled)"));
            }
        },
    };
    let film_node = o.take_object(r, "film")?;
    let film = match film_node {
        Some(f) => read_film(r, f)?,
        None => (768, 576), // Mitsuba's default hdrfilm
    };
    if let Some(s) = o.take_object(r, "sampler")? {
        read_sampler(r, s)?;
    }
    o.finish(r, "fov, fov_axis, near_clip, far_clip, to_world; film, sampler")?;
    let fov_axis = match axis.as_ref().map(|(p, s)| (*p, s.as_str())) {
        None | Some((_, "x")) => FovAxis::X,
        Some((_, "y")) => FovAxis::Y,
        Some((_, "smaller")) => {
            if film.0 <= film.1 {
                FovAxis::X
            } else {
                FovAxis::Y
            }
        }
        Some((_, "larger")) => {
            if film.0 >= film.1 {
                FovAxis::X
            } else {
                FovAxis::Y
            }
        }
        Some((p, other)) => {
            return Err(r.error(p, format!("fov_axis {other:?} is not modelled (x, y, smaller, larger)")));
        }
    };
    let film_value =
        Film::new(film.0, film.1).map_err(|e| r.error(film_node.unwrap_or(node), e.to_string()))?;
    let desc =
        CameraDesc { origin: v3(origin), target: v3(target), up: v3(up), fov_deg, fov_axis, near_clip };
    check_camera(desc, film_value).map_err(|e| r.error(node, e.to_string()))?;
    let camera = CameraOut {
        kind: "perspective",
        origin,
        target,
        up,
        fov_deg,
        fov_axis: match fov_axis {
            FovAxis::X => "x",
            FovAxis::Y => "y",
        },
        near_clip,
    };
    Ok((camera, FilmOut { width: film.0, height: film.1, pixel_filter: "box" }))
}

fn read_film(r: &Reader, node: Node) -> Result<(u32, u32), LoadError> {
    if kind(r, node)? != "hdrfilm" {
        return Err(r.error(node, "not modelled by picomis (hdrfilm)"));
    }
    let mut o = Obj::new(r, node)?;
    let mut size = [768, 576];
    for (s, key) in size.iter_mut().zip(["width", "height"]) {
        if let Some(p) = o.take(key) {
            *s = r.count(p, 16384)?;
        }
    }
    if let Some(p) = o.take("pixel_format") {
        let f = r.string(p)?;
        if f != "rgb" && f != "rgba" {
            return Err(r.error(p, format!("pixel_format {f:?} is not modelled (rgb, rgba)")));
        }
    }
    // Border sampling only matters for filters wider than a pixel; the box filter is not.
    if let Some(p) = o.take("sample_border") {
        r.boolean(p)?;
    }
    if let Some(p) = o.take("component_format") {
        r.string(p)?;
    }
    if let Some(f) = o.take_object(r, "rfilter")? {
        if kind(r, f)? != "box" {
            return Err(r.error(f, "not modelled by picomis (box)"));
        }
        let mut fo = Obj::new(r, f)?;
        if let Some(p) = fo.take("radius") {
            if r.float(p)? != 0.5 {
                return Err(r.error(p, "a box filter of radius other than 0.5 (one pixel) is not modelled"));
            }
        }
        fo.finish(r, "radius")?;
    }
    o.finish(r, "width, height, pixel_format, component_format, sample_border; rfilter")?;
    Ok((size[0], size[1]))
}

/// Samplers change the noise, not the expected image: their settings are accepted and left to
/// picomis' own `--spp` and `--seed`.
fn read_sampler(r: &Reader, node: Node) -> Result<(), LoadError> {
    let known = ["independent", "stratified", "multijitter", "orthogonal", "ldsampler"];
    if !known.contains(&kind(r, node)?.as_str()) {
        return Err(r.error(
            node,
            "not modelled by picomis (independent, stratified, multijitter, orthogonal, ldsampler)",
        ));
    }
    let mut o = Obj::new(r, node)?;
    for key in ["sample_count", "seed"] {
        if let Some(p) = o.take(key) {
            r.count(p, u32::MAX)?;
        }
    }
    if let Some(p) = o.take("jitter") {
        r.boolean(p)?;
    }
    o.finish(r, "sample_count, seed, jitter")
}

fn bsdf(r: &Reader, node: Node) -> Result<MaterialOut, LoadError> {
    let mut o = Obj::new(r, node)?;
    let (material, out) = match kind(r, node)?.as_str() {
        "diffuse" => {
            let albedo = o.take("reflectance").map(|p| r.color(p)).transpose()?.unwrap_or([0.5; 3]);
            o.finish(r, "reflectance")?;
            (Material::lambertian(v3(albedo)), MaterialOut::Lambertian { albedo })
        }
        "roughconductor" => {
            match o.take("distribution") {
                Some(p) => {
                    let d = r.string(p)?;
                    if d != "ggx" {
                        return Err(r.error(p, format!("distribution {d:?} is not modelled (ggx)")));
                    }
                }
                None => {
                    return Err(r.error(node, "Mitsuba's default distribution (beckmann) is not modelled: give <string name=\"distribution\" value=\"ggx\">"));
                }
            }
            if let Some(p) = o.take("material") {
                let m = r.string(p)?;
                if m != "none" {
                    return Err(r.error(p, format!("material {m:?} is not modelled (none: Fresnel one)")));
                }
            }
            for key in ["alpha_u", "alpha_v"] {
                if let Some(p) = o.take(key) {
                    return Err(r.error(p, "anisotropic roughness is not modelled (use alpha)"));
                }
            }
            let alpha = o.take("alpha").map(|p| r.float(p)).transpose()?.unwrap_or(0.1);
            let reflectance =
                o.take("specular_reflectance").map(|p| r.color(p)).transpose()?.unwrap_or([1.0; 3]);
            // Visible-normal sampling changes the noise, not the expected image.
            if let Some(p) = o.take("sample_visible") {
                r.boolean(p)?;
            }
            o.finish(r, "distribution, alpha, material, specular_reflectance, sample_visible")?;
            (
                Material::ggx_conductor(alpha, v3(reflectance)),
                MaterialOut::GgxConductor { alpha, fresnel: "one", specular_reflectance: reflectance },
            )
        }
        _ => return Err(r.error(node, format!("not modelled by picomis ({BSDFS})"))),
    };
    material.map_err(|e| r.error(node, e.to_string()))?;
    Ok(out)
}

/// An area emitter inside a shape: its radiance.
fn area_emitter(r: &Reader, node: Node) -> Result<EmitterOut, LoadError> {
    if kind(r, node)? != "area" {
        return Err(r.error(node, "not modelled by picomis inside a shape (area)"));
    }
    let mut o = Obj::new(r, node)?;
    let p = o.take("radiance").ok_or_else(|| r.error(node, "missing <rgb name=\"radiance\">"))?;
    let radiance = r.color(p)?;
    if radiance.iter().any(|&c| c < 0.0) {
        return Err(r.error(p, "radiance must be >= 0"));
    }
    o.finish(r, "radiance")?;
    Ok(EmitterOut { kind: "area", radiance })
}

fn read_shape(r: &Reader, node: Node, materials: &mut Materials) -> Result<ShapeOut, LoadError> {
    let shape_kind = kind(r, node)?;
    if shape_kind != "sphere" && shape_kind != "rectangle" {
        return Err(r.error(node, "not modelled by picomis (sphere, rectangle)"));
    }
    let mut o = Obj::new(r, node)?;
    // A shape exported under its material's name plus the suffix gets that name back.
    let name = r.attr(node, "id")?.map(|id| match id.strip_suffix(SHAPE_ID_SUFFIX) {
        Some(stem) if materials.by_id.contains_key(stem) => stem.to_string(),
        _ => id,
    });
    if let Some(p) = o.take("flip_normals") {
        if r.boolean(p)? {
            return Err(r.error(
                p,
                "flipped normals are not modelled (picomis surfaces are one-sided, normals outward)",
            ));
        }
    }
    // The material: a nested <bsdf>, a <ref> to a named one, or Mitsuba's default (diffuse 0.5).
    let inline = o.take_object(r, "bsdf")?;
    let reference = o.take_object(r, "ref")?;
    let material = match (inline, reference) {
        (Some(b), None) => {
            let m = bsdf(r, b)?;
            let base = match (r.attr(b, "id")?, &name) {
                (Some(id), _) => id,
                (None, Some(n)) => format!("{n}_bsdf"),
                (None, None) => "bsdf".into(),
            };
            materials.add(&base, m)
        }
        (None, Some(rf)) => {
            let id = r.need(rf, "id")?;
            if !materials.by_id.contains_key(&id) {
                return Err(r.error(rf, format!("no <bsdf id=\"{id}\">")));
            }
            id
        }
        (None, None) => materials.add("default_diffuse", MaterialOut::Lambertian { albedo: [0.5; 3] }),
        (Some(_), Some(rf)) => return Err(r.error(rf, "a shape has one BSDF: a <bsdf> and a <ref> given")),
    };
    let emitter = o.take_object(r, "emitter")?.map(|e| area_emitter(r, e)).transpose()?;
    let to_world = o.take("to_world");
    let shape = if shape_kind == "sphere" {
        let center = o.take("center").map(|p| r.point(p)).transpose()?.unwrap_or([0.0; 3]);
        let radius = o.take("radius").map(|p| r.float(p)).transpose()?.unwrap_or(1.0);
        o.finish(r, "center, radius, to_world, flip_normals; bsdf, emitter")?;
        let (center, radius) = match to_world {
            None => (center, radius),
            Some(t) => sphere_transform(r, t, center, radius)?,
        };
        Shape::sphere(v3(center), radius).map_err(|e| r.error(node, e.to_string()))?;
        ShapeOut::Sphere { name, center, radius, material, emitter }
    } else {
        o.finish(r, "to_world, flip_normals; bsdf, emitter")?;
        let m = match to_world {
            Some(t) => r.affine(t)?,
            None => Affine::IDENTITY,
        };
        let det = m.det();
        if !(det != 0.0 && det.is_finite()) {
            return Err(r.error(node, "to_world is singular: the rectangle has no normal"));
        }
        // Mitsuba's rectangle is [-1, 1]^2 at z = 0 with normal +z, mapped by to_world (normals
        // by its inverse transpose). Corners in order with cross(p1 - p0, p3 - p0) on that side.
        let at = |x: f64, y: f64| m.point([x, y, 0.0]).map(|v| v as f32);
        let (p0, p2) = (at(-1.0, -1.0), at(1.0, 1.0));
        let (p1, p3) =
            if det > 0.0 { (at(1.0, -1.0), at(-1.0, 1.0)) } else { (at(-1.0, 1.0), at(1.0, -1.0)) };
        Shape::quad([p0, p1, p2, p3].map(v3)).map_err(|e| r.error(node, e.to_string()))?;
        ShapeOut::Quad { name, p0, p1, p2, p3, material, emitter }
    };
    Ok(shape)
}

/// A sphere under `to_world`: Mitsuba composes to_world · translate(center) · scale(radius); the
/// result must be a similarity (uniform scale, rotation, translation) without mirroring.
fn sphere_transform(
    r: &Reader,
    t: Node,
    center: [f32; 3],
    radius: f32,
) -> Result<([f32; 3], f32), LoadError> {
    let m = r.affine(t)?;
    let f = |v: [f32; 3]| v.map(f64::from);
    let inner = Affine::scale([f64::from(radius); 3]).after(&Affine::IDENTITY);
    let inner = Affine::translate(f(center)).after(&inner);
    let m = m.after(&inner);
    let cols = [m.column(0), m.column(1), m.column(2)];
    let r2 = dot(cols[0], cols[0]);
    let tol = 1e-6 * r2;
    let similar = (0..3).all(|i| (dot(cols[i], cols[i]) - r2).abs() <= tol)
        && (0..3).all(|i| (0..i).all(|j| dot(cols[i], cols[j]).abs() <= tol));
    if !similar || r2.is_nan() || r2 <= 0.0 {
        return Err(r.error(
            t,
            "a sphere's to_world must be translate, rotate and uniform scale (no shear or non-uniform scale)",
        ));
    }
    if dot(cross(cols[0], cols[1]), cols[2]) < 0.0 {
        return Err(r.error(t, "a mirroring to_world turns the sphere inside out: not modelled"));
    }
    let c = m.point([0.0; 3]).map(|v| v as f32);
    Ok((c, r2.sqrt() as f32))
}

fn read_point(r: &Reader, node: Node) -> Result<PointOut, LoadError> {
    match kind(r, node)?.as_str() {
        "point" => {}
        "area" => return Err(r.error(node, "an area emitter belongs inside a <shape>")),
        _ => return Err(r.error(node, "not modelled by picomis (point; area inside a shape)")),
    }
    let mut o = Obj::new(r, node)?;
    let position = o.take("position").map(|p| r.point(p)).transpose()?;
    let to_world = o.take("to_world");
    let position = match (position, to_world) {
        (Some(p), None) => p,
        (None, Some(t)) => r.affine(t)?.point([0.0; 3]).map(|v| v as f32),
        (None, None) => [0.0; 3],
        (Some(_), Some(t)) => return Err(r.error(t, "give position or to_world, not both")),
    };
    let intensity = o.take("intensity").map(|p| r.color(p)).transpose()?.unwrap_or([1.0; 3]);
    o.finish(r, "position, to_world, intensity")?;
    if !position.iter().all(|v| v.is_finite()) {
        return Err(r.error(node, "position is not finite"));
    }
    if intensity.iter().any(|&c| c < 0.0) {
        return Err(r.error(node, "intensity must be >= 0"));
    }
    Ok(PointOut { kind: "point", name: r.attr(node, "id")?, position, intensity })
}
