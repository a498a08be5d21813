//! Scene builders and estimate runners of the suites: a camera, quads, a shading hit, the list of
//! heuristics to sweep, and running statistics of direct-lighting and traced estimates.

use picomis::{
    CameraDesc, FovAxis, Heuristic, Hit, Method, Ray, RenderSettings, Sampler, SamplerKind, ShapeId,
    SurfacePoint, TechniqueEstimate, Vec3,
};
use picomis_host::{HostScene, renderer};

use crate::stats::{MeanEstimate, RgbStats};

/// Every heuristic of the kernel's list ([`picomis::Method::ALL`], default parameters) and the
/// power heuristic with beta 0.5, for tests that sweep them all.
pub fn heuristics() -> Vec<Heuristic> {
    let mut all: Vec<Heuristic> = Method::ALL
        .iter()
        .filter_map(|m| match m {
            Method::Mis(h) => Some(*h),
            _ => None,
        })
        .collect();
    all.push(Heuristic::Power { beta: 0.5 });
    all
}

/// A camera looking down at the origin from +y (tests mostly shade hand-built points).
pub fn camera() -> CameraDesc {
    CameraDesc {
        origin: Vec3::new(0.0, 6.0, 6.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_deg: 30.0,
        fov_axis: FovAxis::Y,
        near_clip: 0.0,
    }
}

/// The corners of the parallelogram `p0, p0 + e1, p0 + e1 + e2, p0 + e2` (front side along
/// e1 x e2).
pub fn quad_corners(p0: Vec3, e1: Vec3, e2: Vec3) -> [Vec3; 4] {
    [p0, p0 + e1, p0 + e1 + e2, p0 + e2]
}

/// A square floor of half-size `half` in the plane y = 0, facing +y.
pub fn floor_corners(half: f32) -> [Vec3; 4] {
    quad_corners(
        Vec3::new(-half, 0.0, half),
        Vec3::new(2.0 * half, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -2.0 * half),
    )
}

/// The hit record of a shading point `p` with front normal `n` on object `object`.
pub fn shading_hit(object: ShapeId, p: Vec3, n: Vec3) -> Hit {
    Hit { t: 1.0, object, point: SurfacePoint { p, n }, front: true }
}

/// `n` direct-lighting estimates at `hit` towards `wo` (estimate i draws from the settings'
/// sample stream for (seed, pixel `stream`, sample i): independent for the independent stream,
/// one scrambled Sobol sequence for sobol, whose mean then varies less than independent ones'), as running statistics of the total radiance and of the
/// light- and BSDF-technique parts, with the number of estimates whose output (contributions or
/// weight sums) was not finite and how many samples of each technique found light.
pub fn direct_stats(
    scene: &HostScene,
    settings: &RenderSettings,
    hit: &Hit,
    wo: Vec3,
    stream: u32,
    n: u32,
) -> DirectStats {
    let it = renderer(scene, settings).expect("the estimator of the settings' strategies");
    let mut out = DirectStats::default();
    for i in 0..n {
        let mut sampler = Sampler::with_kind(settings.sampler(), settings.seed(), stream, i);
        let (light, bsdf) = it.estimate_direct(hit, wo, &mut sampler);
        let finite = |t: &TechniqueEstimate| {
            t.contribution.is_finite() && t.weight_sum.is_finite() && t.weight_sum >= 0.0
        };
        if !(finite(&light) && finite(&bsdf)) {
            out.non_finite += 1;
        }
        out.light_found += u64::from(light.found);
        out.bsdf_found += u64::from(bsdf.found);
        out.total.push(light.contribution + bsdf.contribution);
        out.light.push(light.contribution);
        out.bsdf.push(bsdf.contribution);
    }
    out
}

/// `n` independent estimates of the radiance along `ray` through the estimator's `trace`
/// ([`picomis_host::Renderer::trace`]).
pub fn trace_stats(scene: &HostScene, settings: &RenderSettings, ray: &Ray, stream: u32, n: u32) -> RgbStats {
    let it = renderer(scene, settings).expect("the estimator of the settings' strategies");
    let mut out = RgbStats::default();
    for i in 0..n {
        let mut sampler = Sampler::with_kind(settings.sampler(), settings.seed(), stream, i);
        out.push(it.trace(ray, 0.0, &mut sampler).radiance());
    }
    out
}

/// How many independent scrambles a sobol run of [`direct_run`] and [`trace_run`] is split into
/// (each a Sobol sequence of its own pixel stream): the standard error of their mean comes from
/// the spread of the scrambles' means, with 31 degrees of freedom.
pub const SCRAMBLES: u32 = 32;

/// The pixel stream of scramble `j` of the run of stream `stream`: streams `SCRAMBLES * stream`
/// to `SCRAMBLES * stream + SCRAMBLES - 1`, distinct across runs of distinct streams.
pub fn scramble_stream(stream: u32, j: u32) -> u32 {
    stream.wrapping_mul(SCRAMBLES).wrapping_add(j)
}

/// `n` direct-lighting estimates at `hit` towards `wo` as [`direct_stats`] takes them for the
/// independent stream (estimate i from (seed, `stream`, i)); for sobol, [`SCRAMBLES`] independent
/// scrambles of n / SCRAMBLES estimates each (scramble j: estimates 0.. of pixel stream
/// [`scramble_stream`]), so that the standard error of the mean comes from their spread
/// ([`RunStats::estimate`]) rather than from the independent-sample formula, which overstates the
/// error of a randomised quasi-Monte Carlo mean.
pub fn direct_run(
    scene: &HostScene,
    settings: &RenderSettings,
    hit: &Hit,
    wo: Vec3,
    stream: u32,
    n: u32,
) -> RunStats<DirectStats> {
    direct_run_at(scene, settings, &[(*hit, wo, stream)], n)
}

/// [`direct_run`] at several shading points (hit, view direction, stream), the `n` estimates
/// split evenly among them: for sobol, scramble j of the run takes n / (points x SCRAMBLES)
/// estimates at every point (each from its own stream), so its mean is an independent
/// replica of the run's.
pub fn direct_run_at(
    scene: &HostScene,
    settings: &RenderSettings,
    points: &[(Hit, Vec3, u32)],
    n: u32,
) -> RunStats<DirectStats> {
    let k = points.len() as u32;
    let mut run = RunStats::<DirectStats>::default();
    match settings.sampler() {
        SamplerKind::Independent => {
            for (hit, wo, stream) in points {
                run.stats.merge(&direct_stats(scene, settings, hit, *wo, *stream, n / k));
            }
        }
        SamplerKind::Sobol => {
            run.scrambled = true;
            for j in 0..SCRAMBLES {
                let mut replica = DirectStats::default();
                for (hit, wo, stream) in points {
                    let part = direct_stats(
                        scene,
                        settings,
                        hit,
                        *wo,
                        scramble_stream(*stream, j),
                        n / k / SCRAMBLES,
                    );
                    replica.merge(&part);
                }
                run.replicas.push_means(&replica);
                run.stats.merge(&replica);
            }
        }
    }
    run
}

/// `n` estimates of the radiance along `ray` through the estimator's `trace`, split like
/// [`direct_run`]'s for sobol.
pub fn trace_run(
    scene: &HostScene,
    settings: &RenderSettings,
    ray: &Ray,
    stream: u32,
    n: u32,
) -> RunStats<RgbStats> {
    let mut run = RunStats::default();
    match settings.sampler() {
        SamplerKind::Independent => run.stats = trace_stats(scene, settings, ray, stream, n),
        SamplerKind::Sobol => {
            run.scrambled = true;
            for j in 0..SCRAMBLES {
                let part = trace_stats(scene, settings, ray, scramble_stream(stream, j), n / SCRAMBLES);
                run.replicas.push_means(&part);
                run.stats.merge(&part);
            }
        }
    }
    run
}

/// The statistics of a run of [`direct_run`] or [`trace_run`]: of every estimate (`stats`), and,
/// when the stream is sobol, of the means of its scrambles (`replicas`, one sample per
/// scramble).
#[derive(Clone, Copy, Debug, Default)]
pub struct RunStats<T> {
    /// Statistics of every estimate (for the variance of one estimate).
    pub stats: T,
    /// The means of the scrambles (sobol), one sample each.
    pub replicas: T,
    /// Whether the run is split into scrambles.
    pub scrambled: bool,
}

impl<T> RunStats<T> {
    /// The mean of channel `c` of the `part` of the statistics, with its standard error: the
    /// independent-sample formula for the independent stream, the spread of the scrambles'
    /// means for sobol.
    pub fn estimate(&self, part: impl Fn(&T) -> &RgbStats, c: usize) -> MeanEstimate {
        let all = &part(&self.stats).0[c];
        if self.scrambled {
            MeanEstimate::of_replicas(&part(&self.replicas).0[c], all.n())
        } else {
            MeanEstimate::of_samples(all)
        }
    }
}

impl RunStats<DirectStats> {
    /// [`RunStats::estimate`] of channel `c` of the total (light + BSDF).
    pub fn total(&self, c: usize) -> MeanEstimate {
        self.estimate(|s| &s.total, c)
    }

    /// The estimate of every channel.
    pub fn totals(&self) -> [MeanEstimate; 3] {
        [0, 1, 2].map(|c| self.total(c))
    }
}

impl RunStats<RgbStats> {
    /// [`RunStats::estimate`] of channel `c`.
    pub fn total(&self, c: usize) -> MeanEstimate {
        self.estimate(|s| s, c)
    }

    /// The estimate of every channel.
    pub fn totals(&self) -> [MeanEstimate; 3] {
        [0, 1, 2].map(|c| self.total(c))
    }
}

/// Statistics of direct-lighting estimates: total and per technique.
#[derive(Clone, Copy, Debug, Default)]
pub struct DirectStats {
    /// Light + BSDF contributions.
    pub total: RgbStats,
    /// Light-sampling contribution.
    pub light: RgbStats,
    /// BSDF-sampling contribution.
    pub bsdf: RgbStats,
    /// Estimates with a non-finite contribution or weight sum (or a negative weight sum).
    pub non_finite: u64,
    /// Light samples that found light.
    pub light_found: u64,
    /// BSDF samples that found light.
    pub bsdf_found: u64,
}

impl DirectStats {
    /// Adds the means of `other`'s total and parts as one sample each (the means of a replica).
    pub fn push_means(&mut self, other: &DirectStats) {
        self.total.push_means(&other.total);
        self.light.push_means(&other.light);
        self.bsdf.push_means(&other.bsdf);
    }

    /// Adds the estimates of `other` (for instance those taken at another shading point).
    pub fn merge(&mut self, other: &DirectStats) {
        self.total.merge(&other.total);
        self.light.merge(&other.light);
        self.bsdf.merge(&other.bsdf);
        self.non_finite += other.non_finite;
        self.light_found += other.light_found;
        self.bsdf_found += other.bsdf_found;
    }
}
