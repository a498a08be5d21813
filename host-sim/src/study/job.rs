//! The study of one scene, in its steps: the reference (and the Mitsuba image and the regions,
//! where the scene has them), the ladder, each light alone for the regions, and the equal-time
//! renders. Every step is a method of one [`Context`], which holds what they all read.

use std::path::Path;

use indicatif::ProgressBar;
use picomis::{Arith, Estimate, RenderSettings, Rgb};
use picomis_host::HostScene;
use picomis_host::study::StudyMethod;

use super::args::{EQUAL_TIME_SEED, StudyArgs};
use super::measure::{measured, settings, timed};
use super::methods::{self, defaults_index};
use super::metrics::{self, ErrorStats};
use super::reference::{self, Reference};
use super::regions::{self, RegionMap, RegionStudy};
use super::results::{EqualTime, Record, Rejected, SceneStudy, balance_index, cost_per_spp, f32_twin};
use crate::SimError;
use crate::render::{progress_bar, scene_error};
use crate::scenes::Loaded;

/// The study of one scene.
pub struct SceneJob<'a> {
    /// The scene file.
    pub loaded: &'a Loaded,
    /// The command line.
    pub args: &'a StudyArgs,
    /// Where references are cached.
    pub cache: &'a Path,
}

impl SceneJob<'_> {
    /// Runs the study of `scene`: the job's scene file built for the study film.
    pub fn run(self, scene: &HostScene) -> Result<SceneStudy, SimError> {
        let cx = Context::new(self, scene)?;
        let records = cx.ladder()?;
        let region_study = cx.region_study()?;
        let (budget, equal_time) = cx.equal_time(&records)?;
        Ok(cx.finish(records, equal_time, budget, region_study))
    }
}

/// What every step of one scene's study reads.
struct Context<'a> {
    job: SceneJob<'a>,
    scene: &'a HostScene,
    /// The scene with its ray queries in fixed point, or why fixed point cannot represent it.
    fixed: Result<HostScene, String>,
    /// The methods the scene's arithmetic cannot run.
    rejected: Vec<Rejected>,
    name: String,
    /// The scene's (light, BSDF) samples per camera sample.
    samples: (u16, u16),
    /// The methods ([`methods::methods`]), the last with the scene's own integrator.
    methods: Vec<StudyMethod>,
    ladder: Vec<u32>,
    seeds: Vec<u32>,
    reference: Reference,
    /// The Mitsuba 3 reference (Veach scene).
    mitsuba: Option<Vec<Rgb>>,
    /// Why the Veach scene has no Mitsuba comparison, if it has none.
    mitsuba_note: Option<String>,
    regions: Option<RegionMap>,
}

impl<'a> Context<'a> {
    /// The reference of the scene (rendered or from the cache), the Mitsuba image of the Veach
    /// scene and the scene's regions.
    fn new(job: SceneJob<'a>, scene: &'a HostScene) -> Result<Self, SimError> {
        let name = job.loaded.file.name().to_string();
        let film = scene.film();
        let (w, h) = (film.width(), film.height());
        let samples = job.loaded.file.default_settings().sample_counts();
        // The scene's own integrator (and the flags' errors before anything is rendered).
        let defaults = crate::integrator::integrator(job.loaded, &job.args.integrator, None, 1, 0)?;
        let ref_spp = job.args.reference_spp();
        let reference = reference::get(scene, job.loaded, job.cache, ref_spp, samples, "")?;
        eprintln!(
            "{name}: {w}x{h}, reference {} spp ({}), its own noise: rel. MSE {:.2e}",
            reference.spp,
            if reference.cached {
                "cached".to_string()
            } else {
                format!("rendered in {:.1} s", reference.seconds)
            },
            reference.noise.rel_mse
        );
        let (mitsuba, mitsuba_note) = if name == "veach_mis" {
            match reference::mitsuba(job.args.mitsuba_ref.as_deref(), w, h) {
                Ok(img) => (Some(img), None),
                Err(note) => {
                    eprintln!("{name}: no Mitsuba comparison: {note}");
                    (None, Some(note))
                }
            }
        } else {
            (None, None)
        };
        let regions = RegionMap::find(scene);
        if let Some(r) = &regions {
            eprintln!("{name}: {} plate x light regions", r.regions.len());
        }
        let (ladder, seeds) = (job.args.ladder(), job.args.ladder_seeds());
        let mut fixed = scene.clone();
        let fixed =
            fixed.enable_arith(Arith::Fixed).map(|()| fixed).map_err(|e| scene_error(&job.loaded.file, &e));
        let mut methods = methods::methods();
        methods[defaults_index()] = methods::defaults(&defaults);
        let (n_light, n_bsdf) = defaults.sample_counts();
        eprintln!(
            "{name}: {}: {}, {n_light} light + {n_bsdf} BSDF samples{}",
            methods::DEFAULTS,
            defaults.method(),
            picomis_format::IntegratorDesc::differences(&defaults, picomis::Preset::Best)
                .iter()
                .map(|(k, v)| format!(", {k} {v}"))
                .collect::<String>()
        );
        let rejected: Vec<Rejected> = methods
            .iter()
            .enumerate()
            .filter(|(_, m)| m.extras.arith == Arith::Fixed)
            .filter_map(|(method, _)| {
                fixed.as_ref().err().map(|reason| Rejected { method, reason: reason.clone() })
            })
            .collect();
        for r in &rejected {
            eprintln!("{name}: {}: rejected: {}", methods[r.method].label, r.reason);
        }
        Ok(Self {
            job,
            scene,
            fixed,
            rejected,
            name,
            samples,
            methods,
            ladder,
            seeds,
            reference,
            mitsuba,
            mitsuba_note,
            regions,
        })
    }

    /// The top rung of the ladder.
    fn top(&self) -> u32 {
        *self.ladder.last().unwrap_or(&1)
    }

    /// A progress bar over `spp` summed over the renders to come, per row of the film.
    fn bar(&self, spp: u64, what: &str) -> ProgressBar {
        progress_bar(spp * u64::from(self.scene.film().height()), &format!("{}: {what}", self.name))
    }

    /// Whether method `mi` runs on this scene (its arithmetic can represent the scene).
    fn runs(&self, mi: usize) -> bool {
        self.rejected.iter().all(|r| r.method != mi)
    }

    /// The scene in the arithmetic of method `mi`'s ray queries.
    fn scene_of(&self, mi: usize) -> Result<&HostScene, SimError> {
        match self.methods[mi].extras.arith {
            Arith::F32 => Ok(self.scene),
            Arith::Fixed => self.fixed.as_ref().map_err(|e| SimError::Usage(e.clone())),
        }
    }

    /// The render settings of method `mi` at `spp` with `seed`: the study method's at the scene's
    /// sample counts, or for the defaults the scene's own integrator with the flags.
    fn settings(&self, mi: usize, spp: u32, seed: u32) -> Result<RenderSettings, SimError> {
        if mi == defaults_index() {
            crate::integrator::integrator(self.job.loaded, &self.job.args.integrator, None, spp, seed)
        } else {
            settings(&self.methods[mi], self.samples, spp, seed)
        }
    }

    /// Renders method `mi` at `spp` with `seed`: the estimates, the values errors are measured on,
    /// seconds, and error against the reference.
    fn render(
        &self,
        mi: usize,
        spp: u32,
        seed: u32,
        bar: &ProgressBar,
    ) -> Result<(Vec<Estimate>, Vec<Rgb>, f64, ErrorStats), SimError> {
        let include_emitted = self.job.args.include_emitted;
        let target = if include_emitted { &self.reference.full } else { &self.reference.reflected };
        let scene = self.scene_of(mi)?;
        let (img, seconds) = timed(scene, &self.settings(mi, spp, seed)?, bar)?;
        let values: Vec<Rgb> = img.iter().map(|e| measured(e, include_emitted)).collect();
        let error = metrics::error(&values, target);
        Ok((img, values, seconds, error))
    }

    /// The ladder: every method at every rung with every seed, methods interleaved so that any
    /// change of machine load hits all alike. A method whose ray queries are not f32 is also
    /// measured against its f32 twin of the same rung and seed.
    fn ladder(&self) -> Result<Vec<Record>, SimError> {
        let per_method: u64 =
            self.ladder.iter().map(|&s| u64::from(s)).sum::<u64>() * self.seeds.len() as u64;
        let bar = self.bar(per_method * self.methods.len() as u64, "ladder");
        let mut records = Vec::new();
        for &spp in &self.ladder {
            for &seed in &self.seeds {
                let first = records.len();
                let mut values: Vec<Option<Vec<Rgb>>> = vec![None; self.methods.len()];
                for (mi, slot) in values.iter_mut().enumerate() {
                    if !self.runs(mi) {
                        bar.inc(u64::from(spp) * u64::from(self.scene.film().height()));
                        continue;
                    }
                    let (img, measured, seconds, error) = self.render(mi, spp, seed, &bar)?;
                    let mitsuba = self.mitsuba.as_ref().map(|r| {
                        let full: Vec<Rgb> = img.iter().map(Estimate::radiance).collect();
                        metrics::error(&full, r)
                    });
                    *slot = Some(measured);
                    records.push(Record { method: mi, spp, seed, seconds, error, mitsuba, vs_f32: None });
                }
                for r in &mut records[first..] {
                    let twin = f32_twin(r.method).and_then(|t| values[t].as_ref());
                    if let (Some(img), Some(twin)) = (values[r.method].as_ref(), twin) {
                        r.vs_f32 = Some(metrics::error(img, twin));
                    }
                }
            }
        }
        bar.finish_and_clear();
        Ok(records)
    }

    /// Each light alone at the top rung, for the error per plate x light region (none without
    /// regions).
    fn region_study(&self) -> Result<RegionStudy, SimError> {
        let Some(map) = &self.regions else { return Ok(RegionStudy::default()) };
        let ref_spp = (self.job.args.reference_spp() / 4).max(256);
        let (loaded, cache) = (self.job.loaded, self.job.cache);
        let (samples, top) = (self.samples, self.top());
        // Rejected methods are left out (no region errors), like the methods that choose lights
        // otherwise than uniformly.
        let runs: Vec<bool> = (0..self.methods.len()).map(|mi| self.runs(mi)).collect();
        let settings = |mi, spp, seed| self.settings(mi, spp, seed);
        regions::study(
            self.scene,
            map,
            loaded,
            cache,
            ref_spp,
            samples,
            (&self.methods, &runs, &settings),
            top,
            &self.seeds,
        )
    }

    /// Equal time: every method gets the time balance took at the top rung; returns that budget
    /// and the renders.
    fn equal_time(&self, records: &[Record]) -> Result<(f64, Vec<EqualTime>), SimError> {
        let top = self.top();
        let budget = f64::from(top) * cost_per_spp(records, balance_index(), top);
        let spps: Vec<u32> = (0..self.methods.len())
            .map(|mi| {
                if !self.runs(mi) {
                    return 0;
                }
                let cost = cost_per_spp(records, mi, top);
                ((budget / cost).round() as u32).clamp(1, 1 << 20)
            })
            .collect();
        let bar = self.bar(spps.iter().map(|&s| u64::from(s)).sum(), "equal time");
        let mut equal_time = Vec::new();
        for (mi, &spp) in spps.iter().enumerate().filter(|(mi, _)| self.runs(*mi)) {
            let (img, _, seconds, error) = self.render(mi, spp, EQUAL_TIME_SEED, &bar)?;
            let image = img.iter().map(Estimate::radiance).collect();
            equal_time.push(EqualTime { method: mi, spp, seconds, error, image });
        }
        bar.finish_and_clear();
        Ok((budget, equal_time))
    }

    /// Everything measured, as one [`SceneStudy`].
    fn finish(
        self,
        records: Vec<Record>,
        equal_time: Vec<EqualTime>,
        budget: f64,
        region_study: RegionStudy,
    ) -> SceneStudy {
        let film = self.scene.film();
        let reference_vs_mitsuba = self.mitsuba.as_ref().map(|m| metrics::error(&self.reference.full, m));
        SceneStudy {
            name: self.name,
            width: film.width(),
            height: film.height(),
            records,
            equal_time,
            budget,
            reference: self.reference,
            regions: self.regions,
            region_study,
            mitsuba_note: self.mitsuba_note,
            reference_vs_mitsuba,
            rejected: self.rejected,
        }
    }
}
