//! The analytic control variate: integral f V = integral f (in closed form, `closed_form.rs`)
//! plus integral f (V - 1) (sampled with MIS), for the unoccluded light reaching a Lambertian
//! receiver, for every quad and sphere light ([`On`]); or only for the lights that nothing can
//! block from the receiver ([`Unblocked`]): there V = 1, so f (V - 1) = 0 and the closed form is
//! the exact answer, which needs no samples (they go to the other lights). As a type: the
//! estimator branches on its constants.

crate::choices! {
    /// Whether the unoccluded light reaching a Lambertian receiver is computed in closed form,
    /// with Monte Carlo left for the shadows only.
    pub enum ControlVariate: "control variate" {
        /// Every light is estimated by sampling alone ([`Off`]).
        Off = "off", "every light by sampling alone";
        /// Integral f V = integral f (closed form) + integral f (V - 1) (sampled with MIS) ([`On`]).
        On = "on", "unoccluded light of quad and sphere lights on Lambertian surfaces in closed form, Monte Carlo for the shadows only";
        /// Only for the lights nothing can block from a Lambertian receiver, where it is exact and
        /// needs no samples ([`Unblocked`]).
        Unblocked = "unblocked", "on Lambertian surfaces, the light of quad and sphere lights that nothing can block in closed form (exact: no samples), the others by sampling";
    }
}

/// The control variate of a render, as a type.
pub trait ControlVariateStrategy: 'static {
    /// Its name among the settings.
    const KIND: ControlVariate;
    /// Whether the unoccluded light is in closed form.
    const ON: bool;
    /// Whether only the lights nothing can block are in closed form ([`Unblocked`]).
    const UNBLOCKED: bool = false;
}

/// No control variate.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Off;

impl ControlVariateStrategy for Off {
    const KIND: ControlVariate = ControlVariate::Off;
    const ON: bool = false;
}

/// The analytic control variate on Lambertian receivers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct On;

impl ControlVariateStrategy for On {
    const KIND: ControlVariate = ControlVariate::On;
    const ON: bool = true;
}

/// The closed form only for the lights that nothing can block from a Lambertian receiver (the
/// shadow cull says no object lies between them): there f (V - 1) = 0, so the closed form is
/// exact; selection by contribution gives those lights no samples, and where every light is in
/// closed form no sample is drawn. Never more variance than without it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Unblocked;

impl ControlVariateStrategy for Unblocked {
    const KIND: ControlVariate = ControlVariate::Unblocked;
    const ON: bool = true;
    const UNBLOCKED: bool = true;
}
