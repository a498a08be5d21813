//! Scene builders and estimate runners of the suites: a camera, quads, a shading hit, the list of
//! heuristics to sweep, and running statistics of direct-lighting and traced estimates.

use picomis::{
    CameraDesc, FovAxis, Heuristic, Hit, Method, Ray, RenderSettings, Sampler, ShapeId, SurfacePoint,
    TechniqueEstimate, Vec3,
};
use picomis_host::{HostScene, renderer};

use crate::stats::RgbStats;

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
