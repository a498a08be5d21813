//! The direct-lighting integrator: its settings, the MIS weights and models of Veach and Guibas
//! (1995), the estimator that combines light and BSDF sampling, and the analytic control variate.

pub(crate) mod closed_form;
mod estimator;
mod mis;
pub mod model;
mod settings;

pub use closed_form::{projected_solid_angle, quad_projected_solid_angle, sphere_projected_solid_angle};
pub use estimator::*;
pub use mis::*;
pub use model::MisModel;
pub use settings::*;
