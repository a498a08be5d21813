//! A render's strategies as one type ([`Strategies`]), chosen once: a firmware's build script
//! names the types its scene file asks for, so the binary carries only those; a host matches a
//! render's settings once ([`dispatch`]) and runs the estimator monomorphised for them.

use core::marker::PhantomData;

use crate::error::SceneError;
use crate::integrator::control_variate::{self, ControlVariate, ControlVariateStrategy};
use crate::integrator::model::{self, MisModel, Model};
use crate::integrator::settings::{Given, RenderSettings, SettingsSource};
use crate::light::select::{ByContribution, ByPower, Every, Uniform};
use crate::light::{
    LightSelection, LightStrategies, Lights, LobeMixing, QuadSampling, SphereSampling, lobe, quad, sphere,
};

/// The strategies of a render for scenes of at most `L` lights.
pub trait Strategies<const L: usize>: 'static {
    /// Light selection, sphere and quad sampling, lobe mixing.
    type Lights: LightStrategies<L>;
    /// The analytic control variate, or none.
    type ControlVariate: ControlVariateStrategy;
    /// The multi-sample or the one-sample model.
    type Model: Model;
    /// Where the settings are read: those the estimator was built with, or a constant.
    type Settings: SettingsSource;

    /// Whether `settings` name these strategies (the estimator is built for them only).
    fn check(settings: &RenderSettings) -> Result<(), SceneError> {
        use crate::light::select::Select;
        use crate::light::{lobe::LobeSampler, quad::QuadSampler, sphere::SphereSampler};
        type Lt<St, const L: usize> = <St as Strategies<L>>::Lights;
        let agree = settings.light_selection()
            == <<Lt<Self, L> as LightStrategies<L>>::Selection as Select<L>>::KIND
            && settings.sphere_sampling()
                == <<Lt<Self, L> as LightStrategies<L>>::Spheres as SphereSampler>::KIND
            && settings.quad_sampling() == <<Lt<Self, L> as LightStrategies<L>>::Quads as QuadSampler>::KIND
            && settings.lobe_mixing() == <<Lt<Self, L> as LightStrategies<L>>::Lobe as LobeSampler>::KIND
            && settings.control_variate() == Self::ControlVariate::KIND
            && settings.mis_model().is_one_sample() == Self::Model::ONE_SAMPLE
            && Self::Settings::settings(settings) == *settings;
        if agree { Ok(()) } else { Err(SceneError::StrategyMismatch) }
    }
}

/// The strategies `Lt` (lights), `Cv` (control variate), `Md` (model) and the source of the
/// settings `Src` as one type.
pub struct Direct<Lt, Cv, Md, Src = Given>(PhantomData<Types<(Lt, Cv, Md, Src)>>);

/// The types of a strategy bundle (a function type: the bundle is `Send`, `Sync` and `Copy`
/// whatever they are).
type Types<T> = fn() -> T;

impl<const L: usize, Lt: LightStrategies<L>, Cv: ControlVariateStrategy, Md: Model, Src: SettingsSource>
    Strategies<L> for Direct<Lt, Cv, Md, Src>
{
    type Lights = Lt;
    type ControlVariate = Cv;
    type Model = Md;
    type Settings = Src;
}

/// What [`dispatch`] calls with the strategy types of a render's settings.
pub trait Visit<const L: usize> {
    /// What the visit returns.
    type Output;
    /// Called once, with the strategies as the type `St`.
    fn visit<St: Strategies<L>>(self) -> Self::Output;
}

/// Calls `visitor` with the strategy types that `settings` name (the numbers come from the
/// settings at run time). Every combination is compiled where this is called: a host calls it
/// once per render, a firmware never (its build script names the types).
pub fn dispatch<const L: usize, V: Visit<L>>(settings: &RenderSettings, visitor: V) -> V::Output {
    match settings.light_selection() {
        LightSelection::Uniform => spheres::<L, Uniform, V>(settings, visitor),
        LightSelection::Power => spheres::<L, ByPower<L>, V>(settings, visitor),
        LightSelection::Contribution => spheres::<L, ByContribution<L>, V>(settings, visitor),
        LightSelection::Every => spheres::<L, Every, V>(settings, visitor),
    }
}

fn spheres<const L: usize, Sel: crate::light::Select<L>, V: Visit<L>>(s: &RenderSettings, v: V) -> V::Output {
    match s.sphere_sampling() {
        SphereSampling::Area => quads::<L, Sel, sphere::ByArea, V>(s, v),
        SphereSampling::Cone => quads::<L, Sel, sphere::InCone, V>(s, v),
    }
}

fn quads<const L: usize, Sel: crate::light::Select<L>, Sp: sphere::SphereSampler, V: Visit<L>>(
    s: &RenderSettings,
    v: V,
) -> V::Output {
    match s.quad_sampling() {
        QuadSampling::Area => lobes::<L, Sel, Sp, quad::ByArea, V>(s, v),
        QuadSampling::SolidAngle => lobes::<L, Sel, Sp, quad::SolidAngle, V>(s, v),
        QuadSampling::SolidAngleCosine => lobes::<L, Sel, Sp, quad::SolidAngleCosine, V>(s, v),
        QuadSampling::Auto => lobes::<L, Sel, Sp, quad::Adaptive, V>(s, v),
        QuadSampling::BySize => lobes::<L, Sel, Sp, quad::BySize, V>(s, v),
    }
}

fn lobes<
    const L: usize,
    Sel: crate::light::Select<L>,
    Sp: sphere::SphereSampler,
    Q: quad::QuadSampler,
    V: Visit<L>,
>(
    s: &RenderSettings,
    v: V,
) -> V::Output {
    match s.lobe_mixing() {
        LobeMixing::Off => variates::<L, Lights<Sel, Sp, Q, lobe::Off>, V>(s, v),
        LobeMixing::On => variates::<L, Lights<Sel, Sp, Q, lobe::On>, V>(s, v),
    }
}

fn variates<const L: usize, Lt: LightStrategies<L>, V: Visit<L>>(s: &RenderSettings, v: V) -> V::Output {
    match s.control_variate() {
        ControlVariate::Off => models::<L, Lt, control_variate::Off, V>(s, v),
        ControlVariate::On => models::<L, Lt, control_variate::On, V>(s, v),
        ControlVariate::Auto => models::<L, Lt, control_variate::Auto, V>(s, v),
        ControlVariate::BySize => models::<L, Lt, control_variate::BySize, V>(s, v),
    }
}

fn models<const L: usize, Lt: LightStrategies<L>, Cv: ControlVariateStrategy, V: Visit<L>>(
    s: &RenderSettings,
    v: V,
) -> V::Output {
    match s.mis_model() {
        MisModel::Multi => v.visit::<Direct<Lt, Cv, model::Multi>>(),
        MisModel::One { .. } => v.visit::<Direct<Lt, Cv, model::One>>(),
    }
}

/// The paths of the strategy types that [`dispatch`] calls with, for code that names them (a
/// firmware's build script): `L` stands for the scene's light capacity.
pub mod type_paths {
    use super::*;

    /// The selection's type.
    pub const fn selection(s: LightSelection) -> &'static str {
        match s {
            LightSelection::Uniform => "picomis::light::select::Uniform",
            LightSelection::Power => "picomis::light::select::ByPower<L>",
            LightSelection::Contribution => "picomis::light::select::ByContribution<L>",
            LightSelection::Every => "picomis::light::select::Every",
        }
    }

    /// The sphere sampling's type in a scene without sphere lights (its kind is
    /// [`SphereSampling::Area`]).
    pub const NO_SPHERES: &str = "picomis::light::sphere::Absent";

    /// The quad sampling's type in a scene without quad lights (its kind is
    /// [`QuadSampling::Area`]).
    pub const NO_QUADS: &str = "picomis::light::quad::Absent";

    /// The sphere sampling's type.
    pub const fn spheres(s: SphereSampling) -> &'static str {
        match s {
            SphereSampling::Area => "picomis::light::sphere::ByArea",
            SphereSampling::Cone => "picomis::light::sphere::InCone",
        }
    }

    /// The quad sampling's type.
    pub const fn quads(q: QuadSampling) -> &'static str {
        match q {
            QuadSampling::Area => "picomis::light::quad::ByArea",
            QuadSampling::SolidAngle => "picomis::light::quad::SolidAngle",
            QuadSampling::SolidAngleCosine => "picomis::light::quad::SolidAngleCosine",
            QuadSampling::Auto => "picomis::light::quad::Adaptive",
            QuadSampling::BySize => "picomis::light::quad::BySize",
        }
    }

    /// The lobe mixing's type.
    pub const fn lobe(l: LobeMixing) -> &'static str {
        match l {
            LobeMixing::Off => "picomis::light::lobe::Off",
            LobeMixing::On => "picomis::light::lobe::On",
        }
    }

    /// The control variate's type.
    pub const fn control_variate(c: ControlVariate) -> &'static str {
        match c {
            ControlVariate::Off => "picomis::integrator::control_variate::Off",
            ControlVariate::On => "picomis::integrator::control_variate::On",
            ControlVariate::Auto => "picomis::integrator::control_variate::Auto",
            ControlVariate::BySize => "picomis::integrator::control_variate::BySize",
        }
    }

    /// The model's type.
    pub const fn model(m: MisModel) -> &'static str {
        match m {
            MisModel::Multi => "picomis::integrator::model::Multi",
            MisModel::One { .. } => "picomis::integrator::model::One",
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::string::String;
    use std::vec::Vec;

    use super::*;
    use crate::choice::Choice;
    use crate::integrator::mis::Method;

    /// The last segment of a type's path, generics aside.
    fn ident(path: &str) -> &str {
        let path = path.split('<').next().unwrap_or(path);
        path.rsplit("::").next().unwrap_or(path)
    }

    struct Names;
    impl Visit<4> for Names {
        type Output = Vec<String>;
        fn visit<St: Strategies<4>>(self) -> Vec<String> {
            type Lt<St> = <St as Strategies<4>>::Lights;
            [
                core::any::type_name::<<Lt<St> as LightStrategies<4>>::Selection>(),
                core::any::type_name::<<Lt<St> as LightStrategies<4>>::Spheres>(),
                core::any::type_name::<<Lt<St> as LightStrategies<4>>::Quads>(),
                core::any::type_name::<<Lt<St> as LightStrategies<4>>::Lobe>(),
                core::any::type_name::<St::ControlVariate>(),
                core::any::type_name::<St::Model>(),
            ]
            .iter()
            .map(|p| String::from(ident(p)))
            .collect()
        }
    }

    /// Every combination of settings reaches the types their paths name, and those types
    /// accept the settings ([`Strategies::check`]).
    #[test]
    fn dispatch_reaches_the_types_the_paths_name() {
        let base = RenderSettings::new(Method::ALL[4], 1, 1, 1, 0).unwrap();
        let mut n = 0;
        for &sel in LightSelection::ALL.iter() {
            for &sp in SphereSampling::ALL.iter() {
                for &q in QuadSampling::ALL.iter() {
                    for &lb in LobeMixing::ALL.iter() {
                        for &cv in ControlVariate::ALL.iter() {
                            for &md in <MisModel as Choice>::ALL {
                                let s = base
                                    .with_light_selection(sel)
                                    .with_sphere_sampling(sp)
                                    .with_quad_sampling(q)
                                    .with_lobe_mixing(lb)
                                    .with_mis_model(md)
                                    .unwrap()
                                    .with_control_variate(cv)
                                    .unwrap();
                                let want: Vec<&str> = [
                                    type_paths::selection(sel),
                                    type_paths::spheres(sp),
                                    type_paths::quads(q),
                                    type_paths::lobe(lb),
                                    type_paths::control_variate(cv),
                                    type_paths::model(md),
                                ]
                                .iter()
                                .map(|p| ident(p))
                                .collect();
                                assert_eq!(dispatch::<4, _>(&s, Names), want);
                                struct Check(RenderSettings);
                                impl Visit<4> for Check {
                                    type Output = Result<(), SceneError>;
                                    fn visit<St: Strategies<4>>(self) -> Self::Output {
                                        St::check(&self.0)
                                    }
                                }
                                assert_eq!(dispatch::<4, _>(&s, Check(s)), Ok(()));
                                n += 1;
                            }
                        }
                    }
                }
            }
        }
        assert_eq!(n, 4 * 2 * 5 * 2 * 4 * 2);
        // The types of scenes without sphere or quad lights.
        use crate::light::{quad::QuadSampler, sphere::SphereSampler};
        assert_eq!(ident(type_paths::NO_SPHERES), ident(core::any::type_name::<sphere::Absent>()));
        assert_eq!(ident(type_paths::NO_QUADS), ident(core::any::type_name::<quad::Absent>()));
        assert_eq!((sphere::Absent::KIND, quad::Absent::KIND), (SphereSampling::Area, QuadSampling::Area));
        const { assert!(!sphere::Absent::PRESENT && !quad::Absent::PRESENT && sphere::InCone::PRESENT) };
    }
}
