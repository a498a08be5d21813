//! The analytic control variate: integral f V = integral f (in closed form, `closed_form.rs`)
//! plus integral f (V - 1) (sampled with MIS), for the unoccluded light reaching a Lambertian
//! receiver, for every quad and sphere light ([`On`]); or by a rule measured to pay ([`Auto`]):
//! every light in a scene of area lights only, and only the lights that nothing can block where
//! a scene has point lights; either way, where nothing can block a light, V = 1, so f (V - 1) = 0
//! and the closed form is exact: that light needs no samples (they go to the other lights). As a
//! type: the estimator branches on its constants.

crate::choices! {
    /// Whether the unoccluded light reaching a Lambertian receiver is computed in closed form,
    /// with Monte Carlo left for the shadows only.
    pub enum ControlVariate: "control variate" {
        /// Every light is estimated by sampling alone ([`Off`]).
        Off = "off", "every light by sampling alone";
        /// Integral f V = integral f (closed form) + integral f (V - 1) (sampled with MIS) ([`On`]).
        On = "on", "unoccluded light of quad and sphere lights on Lambertian surfaces in closed form, Monte Carlo for the shadows only";
        /// By the rule of [`Auto`]: every light in a scene of area lights only, the lights nothing
        /// can block where it has point lights; exact lights take no samples.
        Auto = "auto", "as on in a scene of area lights only, else for the lights nothing can block; no samples where the closed form is exact";
        /// As `auto`, but where every area light looks small from the receiver only for the
        /// lights nothing can block ([`BySize`]).
        BySize = "by-size", "as auto, but only for the lights nothing can block where every light looks small from the receiver (measured best)";
    }
}

/// The control variate of a render, as a type.
pub trait ControlVariateStrategy: 'static {
    /// Its name among the settings.
    const KIND: ControlVariate;
    /// Whether the unoccluded light is in closed form.
    const ON: bool;
    /// Whether the rule of [`Auto`] decides which lights are in closed form.
    const AUTO: bool = false;
    /// With [`ControlVariateStrategy::AUTO`]: where every light looks small from the receiver
    /// (extent under this times distance), only the unblocked ones ([`BySize`]).
    const SMALL: Option<f32> = None;
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

/// The control variate by a rule (measured: docs/defaults.md): in a scene of area lights only,
/// every light is in closed form, as with [`On`]; in a scene with point lights, only the lights
/// nothing can block from the receiver (there the samples the other lights of [`On`] would give
/// the covered lights, whose f (V - 1) is mostly zero, would be missed by the point lights, which
/// have no closed form). Where nothing can block a light (the shadow cull says no object lies
/// between it and the receiver), f (V - 1) = 0: its closed form is exact, selection by
/// contribution gives it no samples, and where every light is exact no sample is drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Auto;

impl ControlVariateStrategy for Auto {
    const KIND: ControlVariate = ControlVariate::Auto;
    const ON: bool = true;
    const AUTO: bool = true;
}

/// [`Auto`], but in a scene whose only light is an area light, that light only where it looks
/// large from the receiver (its extent, a quad's diagonal or a sphere's diameter, at least its
/// distance), and elsewhere only where nothing can block it (where it is exact and saves the
/// samples). Over a light that looks small, light samples already follow f and the closed form
/// saves little of their variance for what it costs; with several lights it also removes the
/// variance of choosing among them, and stays on. Measured (docs/defaults.md): on box_quad and
/// diffuse_room the control variate lowers the error by 1-4 % for 30-45 % more time; by size it
/// keeps the gains of low_ceiling (3.6x less error) and lambert_sphere.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BySize;

impl ControlVariateStrategy for BySize {
    const KIND: ControlVariate = ControlVariate::BySize;
    const ON: bool = true;
    const AUTO: bool = true;
    const SMALL: Option<f32> = Some(1.0);
}
