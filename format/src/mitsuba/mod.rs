//! Mitsuba 3 XML scenes in and out.
//!
//! [`import`] reads the subset of Mitsuba 3's scene format that picomis models and writes a
//! `picomis-scene/1` file: a `perspective` sensor (`fov`, `fov_axis`, `near_clip`, `to_world`
//! with one `lookat`), an `hdrfilm` with a `box` filter, `sphere`s (`center`/`radius` or a
//! similarity `to_world`) and `rectangle`s under any affine `to_world` (`matrix`, `translate`,
//! `rotate`, `scale`, `lookat`, composed in order), `diffuse` and `roughconductor` (GGX,
//! isotropic `alpha`, `material` `none`) BSDFs, `area` and `point` emitters, the `direct`
//! integrator, `<default>`s and `$name` references. Anything else is an error naming the file,
//! the line and the element, e.g.
//! `scene.xml:41: <bsdf type="plastic">: not modelled by picomis (diffuse, roughconductor)`.
//!
//! [`export`] writes a scene file as Mitsuba 3 XML. Importing an export gives back the same
//! scene, bit for bit.

mod export;
mod import;
mod json;
mod transform;
mod xml;

pub use export::Export;

/// Mitsuba's ids are one namespace, picomis's shape and material names two: a shape named like a
/// material (Veach's plates) is exported with this suffix, which the importer takes off again.
const SHAPE_ID_SUFFIX: &str = "_shape";

use crate::{LoadError, SceneFile};

/// Converts Mitsuba 3 XML `text` into the text of a `picomis-scene/1` file for a scene called
/// `name`. `file` names the input in errors (`file:line: <element>: reason`). The result is
/// checked by [`SceneFile::parse`] before it is returned.
pub fn import(text: &str, file: &str, name: &str) -> Result<String, LoadError> {
    let json = import::import(text, file, name).map_err(one_line)?;
    SceneFile::parse(&json, file).map_err(one_line)?;
    Ok(json)
}

/// An error on one line: control characters (from the input, or in the XML parser's messages)
/// are escaped.
fn one_line(e: LoadError) -> LoadError {
    let clean = |s: String| {
        if s.chars().any(char::is_control) {
            s.chars()
                .flat_map(|c| if c.is_control() { c.escape_debug().collect::<Vec<_>>() } else { vec![c] })
                .collect()
        } else {
            s
        }
    };
    LoadError { file: clean(e.file), entry: clean(e.entry), reason: clean(e.reason) }
}

/// Reads and converts a Mitsuba 3 XML file (see [`import`]); the scene is named after the file.
pub fn import_file(path: &std::path::Path) -> Result<String, LoadError> {
    let (file, text) = crate::read_bounded(path)?;
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "scene".into());
    import(&text, &file, &name)
}

/// Writes the `picomis-scene/1` file `text` (named `file` in errors) as Mitsuba 3 XML.
pub fn export(text: &str, file: &str) -> Result<Export, LoadError> {
    let scene = SceneFile::parse(text, file)?;
    export::export(&scene, text)
}
