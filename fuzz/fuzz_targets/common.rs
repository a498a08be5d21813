//! What both fuzz targets check of a scene the loader or the importer accepted: it builds with
//! capacities 64 (or has more objects than that), and renders finite pixels.

use picomis::integrator::{control_variate, model};
use picomis::light::select::Uniform;
use picomis::light::{lobe, quad, sphere};
use picomis::{Direct, Film, Heuristic, Integrator, Lights, Method, Preset, RenderSettings};
use picomis_format::SceneFile;

/// The lecture's strategies ([`Preset::Lecture`]): the estimator's types for its settings.
type Lecture =
    Direct<Lights<Uniform, sphere::InCone, quad::ByArea, lobe::Off>, control_variate::Off, model::Multi>;

/// Panics unless `scene` builds (or is too big for the build) and renders finite pixels.
pub fn check_accepted(scene: &SceneFile) {
    let Ok(film) = Film::new(3, 2) else { return };
    let Ok(built) = scene.build_with_film::<64, 64, 64>(film) else {
        let c = scene.counts();
        assert!(c.shapes > 64 || c.lights > 64 || c.materials > 64, "valid scene failed to build");
        return;
    };
    let settings = RenderSettings::new(Method::Mis(Heuristic::Power { beta: 2.0 }), 1, 1, 2, 1)
        .unwrap()
        .with_strategies_of(Preset::Lecture);
    let it = Integrator::<Lecture, 64, 64, 64>::new(&built, &settings).unwrap();
    for (x, y) in [(0, 0), (2, 1)] {
        assert!(it.render_pixel(x, y).radiance().is_finite());
    }
}
