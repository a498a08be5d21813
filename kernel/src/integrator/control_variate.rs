//! The analytic control variate: integral f V = integral f (in closed form, `closed_form.rs`)
//! plus integral f (V - 1) (sampled with MIS), for the unoccluded light reaching a Lambertian
//! receiver. As a type: the estimator branches on [`ControlVariateStrategy::ON`], a constant.

crate::choices! {
    /// Whether the unoccluded light reaching a Lambertian receiver is computed in closed form,
    /// with Monte Carlo left for the shadows only.
    pub enum ControlVariate: "control variate" {
        /// Every light is estimated by sampling alone ([`Off`]).
        Off = "off", "every light by sampling alone";
        /// Integral f V = integral f (closed form) + integral f (V - 1) (sampled with MIS) ([`On`]).
        On = "on", "unoccluded light of quad and sphere lights on Lambertian surfaces in closed form, Monte Carlo for the shadows only";
    }
}

/// The control variate of a render, as a type.
pub trait ControlVariateStrategy: 'static {
    /// Its name among the settings.
    const KIND: ControlVariate;
    /// Whether the unoccluded light is in closed form.
    const ON: bool;
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
