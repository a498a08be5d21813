//! `picomis-sim import` and `picomis-sim export`: Mitsuba 3 XML scenes in and out (the
//! conversion itself is `picomis_format::mitsuba`, shared with the fuzz tests).

use std::path::{Path, PathBuf};

use picomis_format::LoadError;
use picomis_format::mitsuba;

use crate::SimError;
use crate::output::write_atomic;
use crate::scenes::{self, find_builtin};

/// `picomis-sim import`.
#[derive(Debug, clap::Args)]
pub struct ImportArgs {
    /// A Mitsuba 3 XML scene (the subset picomis models: see docs/simulator.md).
    pub scene: PathBuf,
    /// The picomis-scene/1 file to write (default: `<scene stem>.json` here).
    #[arg(long, value_name = "FILE.json")]
    pub out: Option<PathBuf>,
}

/// `picomis-sim export`.
#[derive(Debug, clap::Args)]
pub struct ExportArgs {
    /// A picomis-scene/1 JSON file or the name of a built-in scene (default: veach_mis).
    pub scene: Option<String>,
    /// The Mitsuba 3 XML file to write.
    #[arg(long, value_name = "OUT.xml")]
    pub mitsuba: PathBuf,
}

fn check_folder(path: &Path) -> Result<(), SimError> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if dir.is_dir() {
        Ok(())
    } else {
        Err(SimError::Usage(format!("{}: folder {} does not exist", path.display(), dir.display())))
    }
}

/// Converts a Mitsuba 3 XML file into a picomis-scene/1 file; nothing is written on error.
pub fn import(args: &ImportArgs) -> Result<(), SimError> {
    let stem =
        args.scene.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "scene".into());
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from(format!("{stem}.json")));
    check_folder(&out)?;
    let json = mitsuba::import_file(&args.scene)?;
    write_atomic(&out, json.as_bytes()).map_err(SimError::Io)?;
    let counts = picomis_format::SceneFile::parse(&json, &out.display().to_string())?.counts();
    eprintln!(
        "{}: {} shapes, {} lights, {} materials -> {}",
        args.scene.display(),
        counts.shapes,
        counts.lights,
        counts.materials,
        out.display()
    );
    Ok(())
}

/// Writes a scene as Mitsuba 3 XML.
pub fn export(args: &ExportArgs) -> Result<(), SimError> {
    check_folder(&args.mitsuba)?;
    let arg = args.scene.as_deref().unwrap_or(scenes::DEFAULT_SCENE);
    let loaded = scenes::load(Some(arg))?;
    let text = match loaded.builtin.and_then(find_builtin) {
        Some(b) => b.json.to_string(),
        None => std::fs::read_to_string(arg).map_err(|e| LoadError {
            file: arg.into(),
            entry: "file".into(),
            reason: e.to_string(),
        })?,
    };
    let export = mitsuba::export(&text, loaded.file.file())?;
    for note in &export.notes {
        eprintln!("note: {note}");
    }
    write_atomic(&args.mitsuba, export.xml.as_bytes()).map_err(SimError::Io)?;
    eprintln!("{} -> {}", loaded.file.name(), args.mitsuba.display());
    Ok(())
}
