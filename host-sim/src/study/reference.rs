//! The study's converged reference: the balance heuristic with cone sampling at many samples per
//! pixel, rendered as two independent halves (so its own noise can be estimated) and cached as
//! EXR in `DIR/cache`, keyed by scene name, resolution and a hash of the scene file, the kernel
//! version and a kernel fingerprint (a few camera samples' bits: any kernel change that alters
//! this scene's pixels invalidates the cache). Also loads the Mitsuba 3 reference of the Veach
//! scene.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use picomis::{Estimate, Heuristic, Method, RenderSettings, Rgb, SphereSampling};
use picomis_host::HostScene;

use super::measure::{self, timed};
use super::metrics::{ErrorStats, REL_EPSILON, downsample};
use crate::SimError;
use crate::output::{Format, Image, decode_exr, encode, read_exr, write_atomic};
use crate::render::progress_bar;
use crate::scenes::{Loaded, find_builtin};

/// The kernel's manifest (its version), part of the cache key.
const KERNEL_MANIFEST: &str = include_str!("../../../kernel/Cargo.toml");
/// Bump when the way references are made changes.
const KEY_VERSION: &str = "picomis-study-reference/2";
/// Seeds of the two halves (the ladder uses small seeds, the equal-time renders another one).
const SEEDS: [u32; 2] = [0x5eed_0001, 0x5eed_0002];

/// A converged image of a scene at the study's film.
#[derive(Clone, Debug)]
pub struct Reference {
    /// Samples per pixel.
    pub spp: u32,
    /// Reflected (direct) light per pixel.
    pub reflected: Vec<Rgb>,
    /// Full radiance per pixel (lights seen directly included).
    pub full: Vec<Rgb>,
    /// Expected error of the reference itself (of its reflected light), from its two halves:
    /// a floor under every measured error.
    pub noise: ErrorStats,
    /// Seconds it took to render (0 when it came from the cache).
    pub seconds: f64,
    /// True when it came from the cache.
    pub cached: bool,
    /// The cache key.
    pub key: String,
}

/// 64-bit FNV-1a.
#[derive(Clone, Copy, Debug)]
pub struct Fnv(u64);

impl Fnv {
    /// A fresh hash.
    pub fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
    /// Hashes `bytes` in.
    pub fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }
    /// The hash.
    pub fn finish(self) -> u64 {
        self.0
    }
}

impl Default for Fnv {
    fn default() -> Self {
        Self::new()
    }
}

fn usage(e: picomis::SceneError) -> SimError {
    SimError::Usage(format!("reference settings: {e}"))
}

fn balance(samples: (u16, u16), spp: u32, seed: u32) -> Result<RenderSettings, SimError> {
    RenderSettings::new(Method::Mis(Heuristic::Balance), samples.0.max(1), samples.1.max(1), spp, seed)
        .map(|s| s.with_sphere_sampling(SphereSampling::Cone))
        .map_err(|e| SimError::Usage(format!("reference settings: {e}")))
}

/// The cache key of `loaded`'s scene as built into `scene` (`variant` names a modified copy,
/// e.g. one light alone).
fn key(scene: &HostScene, loaded: &Loaded, samples: (u16, u16), variant: &str) -> Result<String, SimError> {
    let mut h = Fnv::new();
    h.write(KEY_VERSION.as_bytes());
    h.write(variant.as_bytes());
    h.write(KERNEL_MANIFEST.as_bytes());
    match loaded.builtin.and_then(find_builtin) {
        Some(b) => h.write(b.json.as_bytes()),
        None => {
            let text = std::fs::read(loaded.file.file())
                .map_err(|e| SimError::Io(format!("{}: {e}", loaded.file.file())))?;
            h.write(&text);
        }
    }
    h.write(&samples.0.to_le_bytes());
    h.write(&samples.1.to_le_bytes());
    // Kernel fingerprint: 32 x 32 pixels, 2 samples each, with three methods (both techniques,
    // both sphere samplings): any kernel change that alters the scene's pixels is likely caught.
    let film = scene.film();
    let bsdf = RenderSettings::new(Method::BsdfOnly, 1, 1, 2, 7);
    let light = RenderSettings::new(Method::LightOnly, 1, 1, 2, 7)
        .map(|s| s.with_sphere_sampling(SphereSampling::Area));
    let all = [balance(samples, 2, 7)?, bsdf.map_err(usage)?, light.map_err(usage)?];
    for settings in &all {
        let renderer = picomis_host::renderer(scene, settings).map_err(usage)?;
        for j in 0..32 {
            for i in 0..32 {
                let (x, y) = ((2 * i + 1) * film.width() / 64, (2 * j + 1) * film.height() / 64);
                let c = renderer.render_pixel(x, y).radiance();
                for v in [c.x, c.y, c.z] {
                    h.write(&v.to_bits().to_le_bytes());
                }
            }
        }
    }
    let safe: String = loaded
        .file
        .name()
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '-' { c } else { '_' })
        .collect();
    Ok(format!("{safe}_{}x{}_{:016x}", film.width(), film.height(), h.finish()))
}

/// Cached references of `key` (spp and info file), best first.
fn cached(dir: &Path, key: &str) -> Vec<(u32, PathBuf)> {
    let mut found: Vec<(u32, PathBuf)> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .filter_map(|e| {
            let path = e.ok()?.path();
            let name = path.file_name()?.to_str()?;
            let spp =
                name.strip_prefix(key)?.strip_prefix('_')?.strip_suffix("spp_info.txt")?.parse().ok()?;
            Some((spp, path))
        })
        .collect();
    found.sort_by_key(|f| std::cmp::Reverse(f.0));
    found
}

fn files(dir: &Path, key: &str, spp: u32) -> [PathBuf; 3] {
    let base = format!("{key}_{spp}spp");
    [
        dir.join(format!("{base}_reflected.exr")),
        dir.join(format!("{base}_full.exr")),
        dir.join(format!("{base}_info.txt")),
    ]
}

fn parse_info(text: &str) -> Option<(ErrorStats, f64)> {
    let get = |k: &str| -> Option<f64> {
        text.lines().find_map(|l| l.strip_prefix(k)?.strip_prefix('=')?.trim().parse().ok())
    };
    Some((ErrorStats { mse: get("noise_mse")?, rel_mse: get("noise_rel_mse")? }, get("seconds")?))
}

/// The reference of `scene` (`loaded`'s scene, or its `variant`) with at least `min_spp`
/// samples per pixel: from the cache, or rendered and cached.
pub fn get(
    scene: &HostScene,
    loaded: &Loaded,
    dir: &Path,
    min_spp: u32,
    samples: (u16, u16),
    variant: &str,
) -> Result<Reference, SimError> {
    let key = key(scene, loaded, samples, variant)?;
    let film = scene.film();
    let (w, h) = (film.width(), film.height());
    for (spp, _) in cached(dir, &key).into_iter().filter(|(spp, _)| *spp >= min_spp) {
        let [refl, full, info] = files(dir, &key, spp);
        let loaded = (|| -> Option<Reference> {
            let (noise, _) = parse_info(&std::fs::read_to_string(&info).ok()?)?;
            let (a, b) = (read_exr(&refl).ok()?, read_exr(&full).ok()?);
            let fits = |i: &Image| i.width == w && i.height == h;
            (fits(&a) && fits(&b)).then(|| Reference {
                spp,
                reflected: a.data,
                full: b.data,
                noise,
                seconds: 0.0,
                cached: true,
                key: key.clone(),
            })
        })();
        if let Some(r) = loaded {
            return Ok(r);
        }
    }

    // Render two halves with independent seeds.
    let half = min_spp.div_ceil(2);
    let spp = 2 * half;
    let bar =
        progress_bar(u64::from(spp) * u64::from(h), &format!("{}{variant}: reference", loaded.file.name()));
    let mut halves: Vec<Vec<Estimate>> = Vec::new();
    let mut seconds = 0.0;
    for seed in SEEDS {
        let (img, s) = timed(scene, &balance(samples, half, seed)?, &bar)?;
        halves.push(img);
        seconds += s;
    }
    bar.finish_and_clear();
    let (a, b) = (&halves[0], &halves[1]);
    let reflected: Vec<Rgb> = a
        .iter()
        .zip(b)
        .map(|(a, b)| {
            (a.light.contribution + a.bsdf.contribution + b.light.contribution + b.bsdf.contribution) * 0.5
        })
        .collect();
    let full: Vec<Rgb> = a.iter().zip(b).map(|(a, b)| (a.radiance() + b.radiance()) * 0.5).collect();
    // The variance of the mean of two halves is about (A - B)^2 / 4 per value.
    let (mut mse, mut rel) = (0.0, 0.0);
    for ((ea, eb), r) in a.iter().zip(b).zip(&reflected) {
        let (va, vb) = (measure::reflected(ea), measure::reflected(eb));
        for (x, y, rv) in [(va.x, vb.x, r.x), (va.y, vb.y, r.y), (va.z, vb.z, r.z)] {
            let d = f64::from(x) - f64::from(y);
            let var = d * d / 4.0;
            mse += var;
            rel += var / (f64::from(rv) * f64::from(rv) + REL_EPSILON);
        }
    }
    let n = (3 * reflected.len()).max(1) as f64;
    let noise = ErrorStats { mse: mse / n, rel_mse: rel / n };

    let [refl_path, full_path, info_path] = files(dir, &key, spp);
    for (data, path) in [(&reflected, &refl_path), (&full, &full_path)] {
        let image = Image { width: w, height: h, data: data.clone() };
        write_atomic(path, &encode(&image, Format::Exr).map_err(SimError::Io)?).map_err(SimError::Io)?;
    }
    let mut info = String::new();
    let _ = writeln!(info, "scene={}{variant}\nwidth={w}\nheight={h}\nspp={spp}", loaded.file.name());
    let _ = writeln!(info, "method=balance, cone sampling, seeds {:#x} and {:#x}", SEEDS[0], SEEDS[1]);
    let _ = writeln!(info, "noise_mse={:e}\nnoise_rel_mse={:e}\nseconds={seconds}", noise.mse, noise.rel_mse);
    write_atomic(&info_path, info.as_bytes()).map_err(SimError::Io)?;
    Ok(Reference { spp, reflected, full, noise, seconds, cached: false, key })
}

/// The Mitsuba 3 reference of the built-in Veach scene (`host-sim/tests/data`), built into the
/// binary like the scene itself, so that an installed `picomis-sim study` compares with it too.
const VEACH_MITSUBA: &[u8] = include_bytes!("../../tests/data/veach_mis.ref.exr");

/// The Mitsuba 3 reference of the Veach scene at `w` x `h` (box-filtered down by an integer
/// factor if it is larger), or why there is none: the EXR file at `path`, by default the one
/// built into the binary.
pub fn mitsuba(path: Option<&Path>, w: u32, h: u32) -> Result<Vec<Rgb>, String> {
    let (img, path) = match path {
        Some(p) => (read_exr(p)?, p.display().to_string()),
        None => (decode_exr(VEACH_MITSUBA)?, "the built-in Mitsuba 3 reference".to_string()),
    };
    if img.width == w && img.height == h {
        return Ok(img.data);
    }
    let k = img.width / w;
    if k >= 1 && img.width == k * w && img.height == k * h {
        return Ok(downsample(&img.data, img.width, img.height, k));
    }
    Err(format!("{path}: {}x{} is not a multiple of the study film {w}x{h}", img.width, img.height))
}
