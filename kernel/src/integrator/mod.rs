//! The direct-lighting integrator: its settings and presets, the MIS weights and models of Veach
//! and Guibas (1995), the estimator that combines light and BSDF sampling, and the analytic
//! control variate. The strategies of a render are types ([`Strategies`]), chosen once.
//!
//! | file | what |
//! |---|---|
//! | `settings.rs` | [`RenderSettings`], the [`Preset`]s they start from, and where the estimator reads them ([`SettingsSource`]) |
//! | `mis.rs` | the heuristics and the methods that combine the techniques ([`Method`]) |
//! | `model.rs` | the multi-sample and one-sample models ([`MisModel`]; types [`model::Multi`], [`model::One`]) |
//! | `control_variate.rs` | the analytic control variate ([`ControlVariate`]; types [`control_variate::Off`], [`control_variate::On`], [`control_variate::Auto`], [`control_variate::BySize`]) |
//! | `closed_form.rs` | the closed forms of unoccluded light on Lambertian receivers |
//! | `strategies.rs` | the strategies as one type ([`Strategies`], [`Direct`]) and [`dispatch`] |
//! | `estimate.rs` | what the estimator returns ([`Estimate`], [`TechniqueEstimate`]) |
//! | `estimator.rs` | the estimator itself ([`Integrator`]) |

pub(crate) mod closed_form;
pub mod control_variate;
mod estimate;
mod estimator;
mod mis;
pub mod model;
mod settings;
mod strategies;

pub use closed_form::{projected_solid_angle, quad_projected_solid_angle, sphere_projected_solid_angle};
pub use control_variate::{ControlVariate, ControlVariateStrategy};
pub use estimate::{Estimate, MAX_CONTRIBUTION, TechniqueEstimate};
pub use estimator::{Integrator, Shading};
pub use mis::{Heuristic, Method, Technique};
pub use model::{MisModel, Model};
pub use settings::{ConstSettings, Given, Preset, RenderSettings, SettingsSource};
pub use strategies::{Direct, Strategies, Visit, dispatch};
// Public for picomis-format's code generator (the type paths it writes into a firmware's scene
// module); not API.
#[doc(hidden)]
pub use strategies::type_paths;
