//! Combination weights of multiple importance sampling (Veach and Guibas 1995), and the one home
//! of the methods: their names, defaults, validation and the list of all of them
//! ([`Method::ALL`]); the command line, the scene format and the reports ask here.
//!
//! Every heuristic sees the techniques' `q_i = n_i p_i(x)` and returns weights that sum to one
//! wherever some `q_i > 0` (W1) and are zero wherever `q_i = 0` (W2). Values are first scaled by
//! the largest `q`, so 0/0, inf/inf and overflow of `q^beta` cannot happen.

use core::fmt;

use crate::choice::Choice;
use crate::error::{Field, SceneError};

/// A weighting heuristic over any number of techniques.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Heuristic {
    /// Arithmetic average: w_i = 1/n over the techniques that can produce x (the lecture's "very
    /// bad" combination: it keeps the faults of each technique).
    Average,
    /// Balance heuristic: w_i = q_i / sum_k q_k (the lecture's "very good" one).
    Balance,
    /// Power heuristic: w_i = q_i^beta / sum_k q_k^beta (beta = 1 is balance).
    Power {
        /// The exponent, finite and positive.
        beta: f32,
    },
    /// Maximum heuristic: all weight to the largest q_i (ties: the first).
    Maximum,
    /// Cutoff heuristic: drop every q_i < alpha q_max, balance the rest.
    Cutoff {
        /// The threshold, in [0, 1].
        alpha: f32,
    },
}

impl Heuristic {
    /// The power heuristic's default exponent.
    pub const DEFAULT_BETA: f32 = 2.0;
    /// The cutoff heuristic's default threshold.
    pub const DEFAULT_ALPHA: f32 = 0.1;

    /// The power heuristic with exponent `beta` (finite and positive).
    pub const fn power(beta: f32) -> Result<Self, SceneError> {
        Heuristic::Power { beta }.validated()
    }

    /// The cutoff heuristic with threshold `alpha` (in [0, 1]).
    pub const fn cutoff(alpha: f32) -> Result<Self, SceneError> {
        Heuristic::Cutoff { alpha }.validated()
    }

    /// The heuristic if its parameter is valid: beta finite and positive, alpha in [0, 1].
    pub const fn validated(self) -> Result<Self, SceneError> {
        match self {
            Heuristic::Power { beta } if !(beta.is_finite() && beta > 0.0) => {
                Err(SceneError::OutOfRange(Field::Beta))
            }
            Heuristic::Cutoff { alpha } if !(alpha >= 0.0 && alpha <= 1.0) => {
                Err(SceneError::OutOfRange(Field::CutoffAlpha))
            }
            _ => Ok(self),
        }
    }

    /// The weights of all techniques for one sample point, given `q_i = n_i p_i(x)`.
    /// Negative or NaN entries count as zero; infinite entries dominate all finite ones.
    #[inline(always)]
    pub fn weights<const N: usize>(&self, q: [f32; N]) -> [f32; N] {
        // Scale into r_i = q_i / q_max in [0, 1].
        let q = q.map(|v| if v > 0.0 { v } else { 0.0 });
        let q_max = q.iter().fold(0.0f32, |m, &v| if v > m { v } else { m });
        if q_max <= 0.0 {
            return [0.0; N];
        }
        let r = if q_max.is_finite() {
            // (The largest entry's ratio is one: no division for it, the same bits.)
            q.map(|v| if v.to_bits() == q_max.to_bits() { 1.0 } else { v / q_max })
        } else {
            q.map(|v| if v.is_infinite() { 1.0 } else { 0.0 })
        };
        let normalize = |x: [f32; N]| {
            let total: f32 = x.iter().sum();
            // total >= the largest x_i, which is 1 for every heuristic below.
            x.map(|v| v / total)
        };
        match *self {
            Heuristic::Average => normalize(r.map(|v| if v > 0.0 { 1.0 } else { 0.0 })),
            Heuristic::Balance => normalize(r),
            Heuristic::Power { beta } => normalize(r.map(|v| power(v, beta))),
            Heuristic::Maximum => {
                let first = r.iter().position(|&v| v >= 1.0);
                let mut w = [0.0; N];
                if let Some(slot) = first.and_then(|i| w.get_mut(i)) {
                    *slot = 1.0;
                }
                w
            }
            Heuristic::Cutoff { alpha } => normalize(r.map(|v| if v >= alpha && v > 0.0 { v } else { 0.0 })),
        }
    }
}

/// `v^beta` for `v` in [0, 1], with the usual exponents computed exactly and cheaply.
#[inline]
fn power(v: f32, beta: f32) -> f32 {
    if !(v > 0.0) {
        0.0
    } else if v.to_bits() == 1.0f32.to_bits() {
        1.0 // the largest entry: 1^beta, no multiply
    } else if beta == 2.0 {
        v * v
    } else if beta == 1.0 {
        v
    } else if beta == 3.0 {
        v * v * v
    } else {
        crate::num::powf(v, beta)
    }
}

/// The two techniques of direct lighting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Technique {
    /// Sampling a point (or direction) on a light, converted to solid angle.
    Light,
    /// Sampling the BSDF and tracing a ray.
    Bsdf,
}

/// How the light and BSDF techniques are used and combined. `Display` writes the name,
/// [`Method::from_name`] reads it (with default parameters).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Method {
    /// Light sampling alone (no BSDF samples are drawn).
    LightOnly,
    /// BSDF sampling alone (no light samples are drawn; point lights are unreachable).
    BsdfOnly,
    /// Both techniques, combined by a heuristic.
    Mis(Heuristic),
}

impl Method {
    /// Every method, each heuristic with its default parameter, in the lecture's order: each
    /// technique alone, then the combinations from worst to best known.
    pub const ALL: [Method; 7] = [
        Method::BsdfOnly,
        Method::LightOnly,
        Method::Mis(Heuristic::Average),
        Method::Mis(Heuristic::Balance),
        Method::Mis(Heuristic::Power { beta: Heuristic::DEFAULT_BETA }),
        Method::Mis(Heuristic::Maximum),
        Method::Mis(Heuristic::Cutoff { alpha: Heuristic::DEFAULT_ALPHA }),
    ];

    /// The method's name (command line, scene files, reports).
    pub fn name(&self) -> &'static str {
        match self {
            Method::BsdfOnly => "bsdf",
            Method::LightOnly => "light",
            Method::Mis(Heuristic::Average) => "average",
            Method::Mis(Heuristic::Balance) => "balance",
            Method::Mis(Heuristic::Power { .. }) => "power",
            Method::Mis(Heuristic::Maximum) => "maximum",
            Method::Mis(Heuristic::Cutoff { .. }) => "cutoff",
        }
    }

    /// One line about the method (command-line help).
    pub fn summary(&self) -> &'static str {
        match self {
            Method::BsdfOnly => "BSDF sampling alone",
            Method::LightOnly => "light sampling alone",
            Method::Mis(Heuristic::Average) => "arithmetic average of the two techniques",
            Method::Mis(Heuristic::Balance) => "balance heuristic",
            Method::Mis(Heuristic::Power { .. }) => "power heuristic (exponent beta)",
            Method::Mis(Heuristic::Maximum) => "maximum heuristic",
            Method::Mis(Heuristic::Cutoff { .. }) => "cutoff heuristic (threshold alpha)",
        }
    }

    /// The method if its parameters are valid (see [`Heuristic::validated`]).
    pub const fn validated(self) -> Result<Self, SceneError> {
        match self {
            Method::Mis(h) => mis(h.validated()),
            single => Ok(single),
        }
    }

    /// The power heuristic's exponent, if this is the power heuristic.
    pub fn beta(&self) -> Option<f32> {
        match *self {
            Method::Mis(Heuristic::Power { beta }) => Some(beta),
            _ => None,
        }
    }

    /// The cutoff heuristic's threshold, if this is the cutoff heuristic.
    pub fn alpha(&self) -> Option<f32> {
        match *self {
            Method::Mis(Heuristic::Cutoff { alpha }) => Some(alpha),
            _ => None,
        }
    }

    /// The same method with the power heuristic's exponent replaced by `beta` and the cutoff
    /// heuristic's threshold by `alpha` where given (other methods have neither and are kept),
    /// validated.
    pub const fn with_parameters(self, beta: Option<f32>, alpha: Option<f32>) -> Result<Self, SceneError> {
        match (self, beta, alpha) {
            (Method::Mis(Heuristic::Power { .. }), Some(beta), _) => mis(Heuristic::power(beta)),
            (Method::Mis(Heuristic::Cutoff { .. }), _, Some(alpha)) => mis(Heuristic::cutoff(alpha)),
            (m, ..) => m.validated(),
        }
    }

    /// Sample counts actually drawn for the requested `(n_light, n_bsdf)`.
    #[inline]
    pub const fn sample_counts(&self, n_light: u16, n_bsdf: u16) -> (u16, u16) {
        match self {
            Method::LightOnly => (n_light, 0),
            Method::BsdfOnly => (0, n_bsdf),
            Method::Mis(_) => (n_light, n_bsdf),
        }
    }

    /// Weight of a sample of `technique`, given `q_light = n_light p_light(x)` and
    /// `q_bsdf = n_bsdf p_bsdf(x)` for the same direction.
    #[inline]
    pub fn weight(&self, technique: Technique, q_light: f32, q_bsdf: f32) -> f32 {
        match (self, technique) {
            (Method::LightOnly, Technique::Light) | (Method::BsdfOnly, Technique::Bsdf) => 1.0,
            (Method::LightOnly, Technique::Bsdf) | (Method::BsdfOnly, Technique::Light) => 0.0,
            (Method::Mis(h), _) => {
                let [w_light, w_bsdf] = h.weights([q_light, q_bsdf]);
                match technique {
                    Technique::Light => w_light,
                    Technique::Bsdf => w_bsdf,
                }
            }
        }
    }
}

/// A validated heuristic as a method (`Result::map`, which a `const fn` cannot call).
const fn mis(h: Result<Heuristic, SceneError>) -> Result<Method, SceneError> {
    match h {
        Ok(h) => Ok(Method::Mis(h)),
        Err(e) => Err(e),
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl Choice for Method {
    const WHAT: &'static str = "method";
    const ALL: &'static [Self] = &Method::ALL;

    fn name(self) -> &'static str {
        Method::name(&self)
    }

    fn summary(self) -> &'static str {
        Method::summary(&self)
    }
}

impl Method {
    /// The method called `name` (one of [`Method::ALL`]'s names), with default parameters.
    pub fn from_name(name: &str) -> Option<Method> {
        <Self as Choice>::from_name(name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [Heuristic; 7] = [
        Heuristic::Average,
        Heuristic::Balance,
        Heuristic::Power { beta: 2.0 },
        Heuristic::Power { beta: 0.5 },
        Heuristic::Maximum,
        Heuristic::Cutoff { alpha: 0.1 },
        Heuristic::Cutoff { alpha: 1.0 },
    ];

    const CASES: [[f32; 3]; 10] = [
        [1.0, 2.0, 3.0],
        [1.0, 1.0, 1.0],
        [0.0, 5.0, 0.0],
        [1e-30, 1e30, 1.0],
        [f32::INFINITY, 1.0, 0.0],
        [f32::INFINITY, f32::INFINITY, 1.0],
        [f32::MAX, f32::MAX, f32::MAX],
        [1e-38, 1e-45, 0.0],
        [3.0, 3.0, 1e-3],
        [f32::NAN, 2.0, -1.0],
    ];

    #[test]
    fn partition_of_unity_w1() {
        for h in ALL {
            for q in CASES {
                let w = h.weights(q);
                let sum: f32 = w.iter().sum();
                assert!((sum - 1.0).abs() < 1e-6, "{h:?} {q:?} -> {w:?}");
                assert!(w.iter().all(|v| v.is_finite() && *v >= 0.0));
            }
        }
    }

    #[test]
    fn zero_where_pdf_is_zero_w2() {
        for h in ALL {
            for q in CASES {
                let w = h.weights(q);
                for (wi, qi) in w.iter().zip(q) {
                    if !(qi > 0.0) {
                        assert_eq!(*wi, 0.0, "{h:?} {q:?}");
                    }
                }
            }
            assert_eq!(h.weights([0.0, 0.0]), [0.0, 0.0]);
        }
    }

    #[test]
    fn known_values() {
        assert_eq!(Heuristic::Balance.weights([1.0, 3.0]), [0.25, 0.75]);
        assert_eq!(Heuristic::Power { beta: 2.0 }.weights([1.0, 3.0]), [0.1, 0.9]);
        assert_eq!(Heuristic::Average.weights([1.0, 3.0]), [0.5, 0.5]);
        assert_eq!(Heuristic::Maximum.weights([3.0, 3.0]), [1.0, 0.0]);
        assert_eq!(Heuristic::Cutoff { alpha: 0.5 }.weights([1.0, 3.0]), [0.0, 1.0]);
        assert_eq!(Heuristic::Power { beta: 1.0 }.weights([1.0, 3.0]), [0.25, 0.75]);
    }

    #[test]
    fn names_parse_back_to_the_default_methods() {
        for m in Method::ALL {
            assert_eq!(Method::from_name(m.name()), Some(m));
            assert_eq!(m.validated(), Ok(m));
        }
        assert_eq!(Method::from_name("power"), Some(Method::Mis(Heuristic::Power { beta: 2.0 })));
        assert_eq!(Method::from_name("cutoff"), Some(Method::Mis(Heuristic::Cutoff { alpha: 0.1 })));
        assert_eq!(Method::from_name("nope"), None);
        assert_eq!(
            format!("{}", crate::choice::Names::<Method>::of()),
            "bsdf, light, average, balance, power, maximum or cutoff"
        );
    }

    #[test]
    fn parameters_are_validated_once() {
        assert_eq!(Heuristic::power(f32::NAN), Err(SceneError::OutOfRange(Field::Beta)));
        assert_eq!(Heuristic::power(0.0), Err(SceneError::OutOfRange(Field::Beta)));
        assert_eq!(Heuristic::cutoff(1.5), Err(SceneError::OutOfRange(Field::CutoffAlpha)));
        assert_eq!(Heuristic::cutoff(1.0), Ok(Heuristic::Cutoff { alpha: 1.0 }));
        let power = Method::Mis(Heuristic::Balance).with_parameters(Some(3.0), Some(0.5));
        assert_eq!(power, Ok(Method::Mis(Heuristic::Balance)), "balance has no parameter");
        let p = Method::from_name("power").unwrap().with_parameters(Some(3.0), None);
        assert_eq!(p.map(|m| m.beta()), Ok(Some(3.0)));
        let c = Method::from_name("cutoff").unwrap().with_parameters(None, Some(-1.0));
        assert_eq!(c, Err(SceneError::OutOfRange(Field::CutoffAlpha)));
    }

    #[test]
    fn methods_pick_their_technique() {
        let m = Method::LightOnly;
        assert_eq!(m.weight(Technique::Light, 0.0, 5.0), 1.0);
        assert_eq!(m.weight(Technique::Bsdf, 1.0, 5.0), 0.0);
        assert_eq!(m.sample_counts(2, 3), (2, 0));
        assert_eq!(Method::BsdfOnly.sample_counts(2, 3), (0, 3));
        let b = Method::Mis(Heuristic::Balance);
        let sum = b.weight(Technique::Light, 2.0, 6.0) + b.weight(Technique::Bsdf, 2.0, 6.0);
        assert_eq!(sum, 1.0);
    }
}
