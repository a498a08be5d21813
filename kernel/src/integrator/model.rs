//! The two sampling models of multiple importance sampling (Veach and Guibas 1995, section 4).
//!
//! - **Multi-sample:** every camera sample draws `n_l` light and `n_b` BSDF samples,
//!   F = sum_i 1/n_i sum_j w_i(X_ij) f(X_ij) / p_i(X_ij), with the heuristics on q_i = n_i p_i.
//! - **One-sample:** every camera sample picks technique i with probability c_i, draws one sample
//!   X from it and returns w_i(X) f(X) / (c_i p_i(X)), with the heuristics on q_i = c_i p_i.
//!   For this model the balance heuristic is provably the best weighting (Veach 1997, theorem
//!   9.4); with it the estimate is f / (c_l p_l + c_b p_b), mixture sampling.

use crate::choice::Choice;
use crate::error::{Field, SceneError};

/// How many samples a camera sample draws, and from which technique.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MisModel {
    /// Every technique draws its own samples (the lecture's model).
    Multi,
    /// One sample per camera sample: the light technique with probability `c_light`, else the
    /// BSDF technique. `c_light` = 1 or 0 are light or BSDF sampling alone.
    One {
        /// Probability of the light technique, in [0, 1].
        c_light: f32,
    },
}

/// The default probability of the light technique in the one-sample model.
pub const DEFAULT_C_LIGHT: f32 = 0.5;

impl MisModel {
    /// The one-sample model with light probability `c_light`, which must be in [0, 1].
    pub const fn one(c_light: f32) -> Result<Self, SceneError> {
        if !c_light.is_finite() {
            return Err(SceneError::NonFinite(Field::CLight));
        }
        if !(c_light >= 0.0 && c_light <= 1.0) {
            return Err(SceneError::OutOfRange(Field::CLight));
        }
        Ok(MisModel::One { c_light })
    }

    /// Whether this is the one-sample model.
    pub const fn is_one_sample(self) -> bool {
        matches!(self, MisModel::One { .. })
    }
}

impl Choice for MisModel {
    const WHAT: &'static str = "MIS model";
    /// Both models, the one-sample one with [`DEFAULT_C_LIGHT`].
    const ALL: &'static [Self] = &[MisModel::Multi, MisModel::One { c_light: DEFAULT_C_LIGHT }];

    fn name(self) -> &'static str {
        match self {
            MisModel::Multi => "multi",
            MisModel::One { .. } => "one",
        }
    }

    fn summary(self) -> &'static str {
        match self {
            MisModel::Multi => "every technique draws its samples (light and BSDF sample counts)",
            MisModel::One { .. } => "one sample per camera sample: light with probability c_light, else BSDF",
        }
    }
}

/// The model of a render, as a type: the estimator branches on [`Model::ONE_SAMPLE`], a
/// constant, so a build carries the code of the model it names only.
pub trait Model: 'static {
    /// Whether each camera sample draws one sample of one technique.
    const ONE_SAMPLE: bool;
}

/// The multi-sample model (the lecture's).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Multi;

impl Model for Multi {
    const ONE_SAMPLE: bool = false;
}

/// The one-sample model (its `c_light` is a number of the settings).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct One;

impl Model for One {
    const ONE_SAMPLE: bool = true;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn c_light_is_validated() {
        assert_eq!(MisModel::one(0.25), Ok(MisModel::One { c_light: 0.25 }));
        assert!(MisModel::one(0.0).is_ok() && MisModel::one(1.0).is_ok());
        assert_eq!(MisModel::one(1.5), Err(SceneError::OutOfRange(Field::CLight)));
        assert_eq!(MisModel::one(-0.1), Err(SceneError::OutOfRange(Field::CLight)));
        assert_eq!(MisModel::one(f32::NAN), Err(SceneError::NonFinite(Field::CLight)));
    }
}
