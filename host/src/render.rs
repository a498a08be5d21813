//! The kernel's estimator for any render's settings, on a host: [`renderer`] matches the
//! settings once and returns the estimator monomorphised for their strategies, behind one
//! trait object ([`Renderer`]): a call per pixel or row, and the inner loop of each pixel without
//! a branch on a strategy. Every host program renders through it, in the one scene type
//! [`HostScene`], so the combinations are compiled once, here.

use picomis::integrator::Visit;
use picomis::{
    Estimate, Hit, Integrator, Ray, RenderSettings, Sampler, Scene, SceneError, Strategies,
    TechniqueEstimate, Vec3, dispatch,
};

/// The shape capacity of scenes on a host.
pub const HOST_SHAPES: usize = 64;
/// The light capacity of scenes on a host.
pub const HOST_LIGHTS: usize = 32;
/// The material capacity of scenes on a host.
pub const HOST_MATERIALS: usize = 32;

/// A scene on a host: room for [`HOST_SHAPES`] shapes, [`HOST_LIGHTS`] lights and
/// [`HOST_MATERIALS`] materials.
pub type HostScene = Scene<HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS>;

/// A render's estimator ([`picomis::Integrator`]) with the strategies of its settings.
pub trait Renderer: Sync {
    /// The settings.
    fn settings(&self) -> RenderSettings;
    /// The HDR estimate of pixel `(x, y)`: the mean of its camera samples.
    fn render_pixel(&self, x: u32, y: u32) -> Estimate;
    /// The pixels of row `y` from column 0, as many as `row` holds.
    fn render_row(&self, y: u32, row: &mut [Estimate]);
    /// Camera sample `index` of pixel `(x, y)`.
    fn camera_sample(&self, x: u32, y: u32, index: u32) -> Estimate;
    /// Radiance along `ray` beyond `t_near`.
    fn trace(&self, ray: &Ray, t_near: f32, sampler: &mut Sampler) -> Estimate;
    /// Radiance along a ray in direction `dir` whose first hit is `hit`.
    fn shade(&self, hit: Option<Hit>, dir: Vec3, sampler: &mut Sampler) -> Estimate;
    /// Direct lighting at `x` towards `wo`: the light and BSDF techniques' parts.
    fn estimate_direct(
        &self,
        x: &Hit,
        wo: Vec3,
        sampler: &mut Sampler,
    ) -> (TechniqueEstimate, TechniqueEstimate);
}

impl<St: Strategies<L> + 'static, const S: usize, const L: usize, const M: usize> Renderer
    for Integrator<'_, St, S, L, M>
where
    Self: Sync,
{
    fn settings(&self) -> RenderSettings {
        Integrator::settings(self)
    }
    fn render_pixel(&self, x: u32, y: u32) -> Estimate {
        Integrator::render_pixel(self, x, y)
    }
    fn render_row(&self, y: u32, row: &mut [Estimate]) {
        for (x, px) in (0..).zip(row.iter_mut()) {
            *px = Integrator::render_pixel(self, x, y);
        }
    }
    fn camera_sample(&self, x: u32, y: u32, index: u32) -> Estimate {
        Integrator::camera_sample(self, x, y, index)
    }
    fn trace(&self, ray: &Ray, t_near: f32, sampler: &mut Sampler) -> Estimate {
        Integrator::trace(self, ray, t_near, sampler)
    }
    fn shade(&self, hit: Option<Hit>, dir: Vec3, sampler: &mut Sampler) -> Estimate {
        Integrator::shade(self, hit, dir, sampler)
    }
    fn estimate_direct(
        &self,
        x: &Hit,
        wo: Vec3,
        sampler: &mut Sampler,
    ) -> (TechniqueEstimate, TechniqueEstimate) {
        Integrator::estimate_direct(self, x, wo, sampler)
    }
}

/// The estimator of `scene` with `settings`, monomorphised for the strategies they name.
pub fn renderer<'a>(
    scene: &'a HostScene,
    settings: &'a RenderSettings,
) -> Result<Box<dyn Renderer + 'a>, SceneError> {
    struct Build<'a> {
        scene: &'a HostScene,
        settings: &'a RenderSettings,
    }
    impl<'a> Visit<HOST_LIGHTS> for Build<'a> {
        type Output = Result<Box<dyn Renderer + 'a>, SceneError>;
        fn visit<St: Strategies<HOST_LIGHTS> + 'static>(self) -> Self::Output {
            let it =
                Integrator::<St, HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS>::new(self.scene, self.settings)?;
            Ok(Box::new(it))
        }
    }
    dispatch(settings, Build { scene, settings })
}
