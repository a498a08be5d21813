//! Combination weights of multiple importance sampling (Veach and Guibas 1995).
//!
//! Every heuristic sees the techniques' `q_i = n_i p_i(x)` and returns weights that sum to one
//! wherever some `q_i > 0` (W1) and are zero wherever `q_i = 0` (W2). Values are first scaled by
//! the largest `q`, so 0/0, inf/inf and overflow of `q^beta` cannot happen.

/// A weighting heuristic over any number of techniques.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Heuristic {
    /// Arithmetic average: w_i = 1/n over the techniques that can produce x (the seed's "very
    /// bad" combination: it keeps the faults of each technique).
    Average,
    /// Balance heuristic: w_i = q_i / sum_k q_k (the seed's "very good" one).
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
    /// The weights of all techniques for one sample point, given `q_i = n_i p_i(x)`.
    /// Negative or NaN entries count as zero; infinite entries dominate all finite ones.
    pub fn weights<const N: usize>(&self, q: [f32; N]) -> [f32; N] {
        // Scale into r_i = q_i / q_max in [0, 1].
        let q = q.map(|v| if v > 0.0 { v } else { 0.0 });
        let q_max = q.iter().fold(0.0f32, |m, &v| if v > m { v } else { m });
        if q_max <= 0.0 {
            return [0.0; N];
        }
        let r = if q_max.is_finite() {
            q.map(|v| v / q_max)
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
    } else if beta == 2.0 {
        v * v
    } else if beta == 1.0 {
        v
    } else if beta == 3.0 {
        v * v * v
    } else {
        crate::math::powf(v, beta)
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

/// How the light and BSDF techniques are used and combined.
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
    /// Sample counts actually drawn for the requested `(n_light, n_bsdf)`.
    #[inline]
    pub fn sample_counts(&self, n_light: u16, n_bsdf: u16) -> (u16, u16) {
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
