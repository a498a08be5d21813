//! Light sampling: the light technique of the estimator. Each way of doing a part of it is a
//! strategy type, chosen once per render ([`LightStrategies`]):
//!
//! | file | what |
//! |---|---|
//! | `sample.rs` | the shading point, the light chosen and the sample drawn (named structs) |
//! | `select/` | how a light is chosen: [`select::Uniform`], [`select::ByPower`], [`select::ByContribution`], or none ([`select::Every`]) |
//! | `sphere.rs` | how sphere lights are sampled: [`sphere::ByArea`], [`sphere::InCone`] |
//! | `quad.rs` | how quad lights are sampled: [`quad::ByArea`], [`quad::SolidAngle`], [`quad::SolidAngleCosine`], [`quad::Adaptive`], [`quad::BySize`] |
//! | `lobe.rs` | whether a glossy receiver's lobe joins the light samples: [`lobe::Off`], [`lobe::On`] |
//! | `sampler.rs` | [`LightSampler`]: the strategies together, as `select` / `pmf` and `sample` / `pdf` pairs |

pub mod lobe;
pub mod quad;
mod sample;
mod sampler;
pub mod select;
pub mod sphere;

pub use lobe::LobeMixing;
pub use quad::QuadSampling;
pub use sample::{LightChoice, LightSample, ShadingPoint};
pub use sampler::{LightSampler, LightStrategies, Lights, SelectionAt};
pub use select::{LightSelection, Residual, Select};
pub use sphere::SphereSampling;
