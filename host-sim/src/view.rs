//! `picomis-sim view`: the device's display on the desktop. An `embedded-graphics-simulator`
//! window at the panel's resolution (default: the M4F board's 160x120 Rgb565) shows the scene
//! rendered progressively, tile by tile, by the kernel's estimator for the settings
//! (`picomis_host::renderer`) into the simulator's `DrawTarget`, in the pixel order and with the
//! Rgb565 values of the kernel's own `render` (the firmware's path). Pass k renders
//! 2^k samples per pixel from scratch, so the image shown after the pass of N spp is exactly
//! `picomis-sim render --spp N --out F.rgb565` (tested under Xvfb, `tests/window.rs`).
//!
//! This module holds what does not need SDL2: the arguments, the state the keys change, and one
//! pass into any `DrawTarget`. The window itself (`view/window.rs`) is behind the cargo feature
//! `window`, so the default build needs no SDL2.

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::Size;
use embedded_graphics_core::pixelcolor::{Rgb565, Rgb888};
use picomis::{
    Estimate, Film, Heuristic, LightSelection, LobeMixing, Method, RenderSettings, RenderStats,
    SphereSampling,
};
use picomis_format::IntegratorDesc;
use picomis_host::Renderer;

use crate::SimError;
use crate::figure;
use crate::scenes::Loaded;

#[cfg(feature = "window")]
mod window;

/// The M4F board's display (firmware/build.rs renders at this size by default).
pub const DEVICE_WIDTH: u32 = 160;
/// The M4F board's display height.
pub const DEVICE_HEIGHT: u32 = 120;

/// Height of the status bar under the image in the window: three lines of the 6x10 font.
pub const STATUS_HEIGHT: u32 = 32;

/// `picomis-sim view`.
#[derive(Debug, clap::Args)]
pub struct ViewArgs {
    /// A picomis-scene/1 JSON file or the name of a built-in scene (default: veach_mis).
    pub scene: Option<String>,
    /// Display width in pixels.
    #[arg(long, default_value_t = DEVICE_WIDTH, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub width: u32,
    /// Display height in pixels.
    #[arg(long, default_value_t = DEVICE_HEIGHT, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub height: u32,
    /// Magnification of the window: each display pixel is scale x scale screen pixels.
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=16))]
    pub scale: u32,
    /// The starting integrator: every key of a scene file's integrator block, as a flag (the
    /// scene file's block over the best preset, these flags over both; the keys then change the
    /// method, beta, alpha, light selection, sphere sampling and lobe mixing).
    #[command(flatten)]
    pub integrator: IntegratorDesc,
    /// Seed.
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// Tile side in pixels (the firmware's default is 16).
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub tile: u32,
    /// Stop refining after this many passes (pass k has 2^(k-1) spp); the window stays open.
    #[arg(long, value_name = "N", default_value_t = 13, value_parser = clap::value_parser!(u32).range(1..=20))]
    pub passes: u32,
}

/// What the window shows: the image, or one technique's weighted contribution or mean MIS
/// weight (the lecture's figures, coloured as in `picomis-sim figure`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// The rendered image.
    Image,
    /// BSDF samples' weighted contribution.
    BsdfContribution,
    /// Light samples' weighted contribution.
    LightContribution,
    /// Mean MIS weight of BSDF samples that found light (viridis; grey where none did).
    BsdfWeight,
    /// Mean MIS weight of light samples that found light.
    LightWeight,
}

impl View {
    /// All views, in the order the `v` key steps through them.
    pub const ALL: [View; 5] =
        [View::Image, View::BsdfContribution, View::LightContribution, View::BsdfWeight, View::LightWeight];

    /// A short label for the status line.
    pub fn label(self) -> &'static str {
        match self {
            View::Image => "image",
            View::BsdfContribution => "bsdf contrib",
            View::LightContribution => "light contrib",
            View::BsdfWeight => "bsdf weight",
            View::LightWeight => "light weight",
        }
    }

    /// The colour of a pixel with estimate `e` in this view.
    pub fn color(self, e: &Estimate) -> Rgb888 {
        let [r, g, b] = match self {
            View::Image => figure::srgb(e.radiance()),
            View::BsdfContribution => figure::srgb(e.bsdf.contribution),
            View::LightContribution => figure::srgb(e.light.contribution),
            View::BsdfWeight => figure::weight(&e.bsdf),
            View::LightWeight => figure::weight(&e.light),
        };
        Rgb888::new(r, g, b)
    }
}

/// What a key asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Next method (`m`), previous method (`M`).
    Method(i32),
    /// Next view (`v`), previous view (`V`).
    View(i32),
    /// beta up (`b`) or down (`B`) by 0.5.
    Beta(i32),
    /// alpha up (`a`) or down (`A`) by 0.05.
    Alpha(i32),
    /// The next light selection of `LightSelection::ALL` (`l`).
    LightSelection,
    /// Sphere sampling: by area or in the cone (`s`).
    SphereSampling,
    /// Lobe mixing on or off (`g`).
    LobeMixing,
    /// Save the last complete pass as PNG (`p`).
    Save,
    /// Close the window (`q`, Escape).
    Quit,
}

/// The keys, for the help text.
pub const KEYS: &str = "keys: m/M method, v/V view, b/B beta +-0.5, a/A alpha +-0.05, l light selection, \
s sphere sampling, g lobe mixing, p save PNG, q quit";

/// What the keys change: method, view, beta, alpha, and in the settings the light selection,
/// sphere sampling and lobe mixing.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewState {
    /// Index into [`Method::ALL`].
    pub method: usize,
    /// The view.
    pub view: View,
    /// Power-heuristic exponent.
    pub beta: f32,
    /// Cutoff-heuristic threshold.
    pub alpha: f32,
    /// The rest of the integrator: the flags over the scene file's block, then the keys' light
    /// selection, sphere sampling and lobe mixing. Its method is replaced by the one of
    /// [`Self::method`], [`Self::beta`] and [`Self::alpha`] in each pass's settings.
    pub keys: IntegratorDesc,
    /// The seed.
    pub seed: u32,
}

/// The method `Method::ALL[index]` with `beta` and `alpha` (the one place the view turns its
/// index into a method).
pub fn method_at(index: usize, beta: f32, alpha: f32) -> Result<Method, String> {
    let method = Method::ALL.get(index).ok_or_else(|| format!("no method {index}"))?;
    method.with_parameters(Some(beta), Some(alpha)).map_err(|e| e.to_string())
}

/// The name of `Method::ALL[index]`.
pub fn method_name_at(index: usize) -> &'static str {
    Method::ALL.get(index).map_or("?", |m| m.name())
}

impl ViewState {
    /// The starting state from the scene and the flags: the integrator that `picomis-sim render`
    /// would use ([`crate::integrator::integrator`]), at 1 spp.
    pub fn new(loaded: &Loaded, args: &ViewArgs) -> Result<Self, SimError> {
        let start = crate::integrator::integrator(loaded, &args.integrator, None, 1, args.seed)?.method();
        let method = Method::ALL.iter().position(|m| m.name() == start.name()).unwrap_or(0);
        let state = ViewState {
            method,
            view: View::Image,
            beta: start.beta().unwrap_or(Heuristic::DEFAULT_BETA),
            alpha: start.alpha().unwrap_or(Heuristic::DEFAULT_ALPHA),
            keys: crate::integrator::keys(loaded, &args.integrator, None),
            seed: args.seed,
        };
        state.settings(1).map_err(|e| SimError::Usage(format!("{}: {e}", loaded.file.name())))?;
        Ok(state)
    }

    /// The render settings of a pass with `spp` samples per pixel.
    pub fn settings(&self, spp: u32) -> Result<RenderSettings, String> {
        let method = method_at(self.method, self.beta, self.alpha)?;
        crate::integrator::with_method(&self.keys, method).settings(spp, self.seed).map_err(|e| e.to_string())
    }

    /// The method with its parameter, for the status line.
    pub fn method_label(&self) -> String {
        match method_name_at(self.method) {
            "power" => format!("power beta {}", self.beta),
            "cutoff" => format!("cutoff alpha {}", self.alpha),
            other => other.to_string(),
        }
    }

    /// Light selection, sphere sampling and lobe mixing, for the status line.
    pub fn sampling_label(&self) -> String {
        let Ok(s) = self.settings(1) else { return String::new() };
        let lobe = if s.lobe_mixing() == LobeMixing::On { ", lobe" } else { "" };
        format!("{}, {}{lobe}", s.light_selection().name(), s.sphere_sampling().name())
    }

    /// Applies a key; true if the image must be rendered again. Methods the scene cannot use
    /// (e.g. BSDF sampling alone with `bsdf_samples` 0) are skipped; beta stays positive and
    /// alpha in [0, 1].
    pub fn apply(&mut self, action: Action) -> bool {
        let step = |i: usize, d: i32, n: usize| (i as i64 + i64::from(d)).rem_euclid(n as i64) as usize;
        /// The option after `current` in `all`.
        fn next<T: Copy + PartialEq>(all: &[T], current: T) -> T {
            let i = all.iter().position(|&c| c == current).unwrap_or(0);
            all[(i + 1) % all.len()]
        }
        match action {
            Action::Method(d) => {
                let start = self.method;
                loop {
                    self.method = step(self.method, d.signum(), Method::ALL.len());
                    if self.method == start || self.settings(1).is_ok() {
                        break;
                    }
                }
                self.method != start
            }
            Action::View(d) => {
                let i = View::ALL.iter().position(|&v| v == self.view).unwrap_or(0);
                self.view = View::ALL[step(i, d.signum(), View::ALL.len())];
                true
            }
            Action::Beta(d) => {
                let old = self.beta;
                self.beta = (self.beta + 0.5 * d as f32).clamp(0.5, 16.0);
                self.beta != old && method_name_at(self.method) == "power"
            }
            Action::Alpha(d) => {
                let old = self.alpha;
                self.alpha = ((self.alpha + 0.05 * d as f32) * 100.0).round().clamp(0.0, 100.0) / 100.0;
                self.alpha != old && method_name_at(self.method) == "cutoff"
            }
            // (The pass's settings are valid: the method keys skip invalid ones, and these
            // strategies fit every method.)
            Action::LightSelection => self.settings(1).is_ok_and(|s| {
                self.keys.light_selection = Some(next(&LightSelection::ALL, s.light_selection()));
                true
            }),
            Action::SphereSampling => self.settings(1).is_ok_and(|s| {
                self.keys.sphere_sampling = Some(next(&SphereSampling::ALL, s.sphere_sampling()));
                true
            }),
            Action::LobeMixing => self.settings(1).is_ok_and(|s| {
                self.keys.lobe_mixing = Some(next(&LobeMixing::ALL, s.lobe_mixing()));
                true
            }),
            Action::Save | Action::Quit => false,
        }
    }
}

/// The samples per pixel of pass `k` (0-based): 1, 2, 4, ...
pub fn pass_spp(k: u32) -> u32 {
    1u32 << k.min(31)
}

/// One pass of `renderer` (the estimator of a scene whose film is `film`, with the pass's
/// settings) into `target`, tile by tile in the order of `picomis::tiles`, each tile row by row
/// through `fill_contiguous`: the pixel order and colours of the kernel's
/// `Integrator::render_tile` (`Rgb565::from(tone_map(radiance))`, the firmware's path) for the
/// image, the figure's colours for the other views.
pub fn render_pass<D>(
    renderer: &dyn Renderer,
    film: Film,
    view: View,
    tile: u32,
    target: &mut D,
) -> Result<RenderStats, D::Error>
where
    D: DrawTarget<Color = Rgb565>,
{
    let spp = renderer.settings().spp();
    let mut total = RenderStats::default();
    for area in picomis::tiles(film, Size::new(tile, tile)) {
        // `tiles` cuts the film itself: every tile lies inside it.
        let (x0, y0) = (area.top_left.x as u32, area.top_left.y as u32);
        let (w, h) = (area.size.width, area.size.height);
        let colors = (y0..y0 + h)
            .flat_map(|y| (x0..x0 + w).map(move |x| Rgb565::from(view.color(&renderer.render_pixel(x, y)))));
        target.fill_contiguous(&area, colors)?;
        total.add(&RenderStats::new(w * h, spp));
    }
    Ok(total)
}

/// Runs `picomis-sim view`.
pub fn run(args: &ViewArgs) -> Result<(), SimError> {
    let loaded = crate::scenes::load(args.scene.as_deref())?;
    let state = ViewState::new(&loaded, args)?;
    let film = Film::new(args.width, args.height)
        .map_err(|e| SimError::Usage(format!("--width {} --height {}: {e}", args.width, args.height)))?;
    #[cfg(feature = "window")]
    {
        window::run(&loaded, film, state, args)
    }
    #[cfg(not(feature = "window"))]
    {
        let _ = (film, state);
        Err(SimError::Usage(
            "view: this picomis-sim was built without the window (SDL2); build it with \
             `cargo run --release -p picomis-sim --features window -- view` (Debian: apt-get install libsdl2-dev)"
                .into(),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state() -> ViewState {
        state_with(&[])
    }

    /// `picomis-sim view FLAGS`' arguments.
    fn args(flags: &[&str]) -> ViewArgs {
        #[derive(clap::Parser)]
        struct View {
            #[command(flatten)]
            args: ViewArgs,
        }
        <View as clap::Parser>::parse_from([&["view"][..], flags].concat()).args
    }

    /// The starting state of `picomis-sim view FLAGS` on the Veach scene.
    fn state_with(flags: &[&str]) -> ViewState {
        let loaded = crate::scenes::load(Some("veach_mis")).unwrap();
        ViewState::new(&loaded, &args(flags)).unwrap()
    }

    #[test]
    fn the_integrator_flags_start_the_view_where_they_say() {
        let flags = ["--mis", "cutoff", "--alpha", "0.2", "--light-selection", "power", "--seed", "5"];
        let s = state_with(&flags);
        assert_eq!((method_name_at(s.method), s.alpha), ("cutoff", 0.2));
        assert_eq!(s.sampling_label(), "power, cone, lobe");
        // Flags the kernel refuses are usage errors, as for render.
        let loaded = crate::scenes::load(Some("veach_mis")).unwrap();
        assert!(matches!(ViewState::new(&loaded, &args(&["--c-light", "0.5"])), Err(SimError::Usage(_))));
    }

    #[test]
    fn keys_cycle_every_method_and_view_and_keep_parameters_valid() {
        let mut s = state();
        assert_eq!(method_name_at(s.method), "power");
        let mut seen = vec![];
        for _ in 0..Method::ALL.len() {
            assert!(s.apply(Action::Method(1)));
            seen.push(method_name_at(s.method));
        }
        seen.sort();
        let mut all: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
        all.sort();
        assert_eq!(seen, all);
        assert!(s.apply(Action::Method(-1)));
        assert_eq!(method_name_at(s.method), "balance");
        for _ in 0..40 {
            s.apply(Action::Beta(-1));
            s.apply(Action::Alpha(1));
        }
        assert_eq!((s.beta, s.alpha), (0.5, 1.0));
        s.method = Method::ALL.iter().position(|m| m.name() == "cutoff").unwrap();
        assert!(s.settings(4).is_ok());
        assert!(!s.apply(Action::Beta(1)), "beta does not change a cutoff render");
        assert!(s.apply(Action::Alpha(-1)));
        assert_eq!(s.alpha, 0.95);
        let views: Vec<View> = (0..5)
            .map(|_| {
                s.apply(Action::View(1));
                s.view
            })
            .collect();
        assert_eq!(views.last(), Some(&View::Image));
        assert_eq!(views.len(), View::ALL.len());
        assert!(s.apply(Action::LightSelection) && s.apply(Action::SphereSampling));
        assert!(
            s.apply(Action::LobeMixing) && s.settings(1).is_ok_and(|s| s.lobe_mixing() == LobeMixing::Off)
        );
        assert_eq!(s.sampling_label(), "uniform, area");
        assert!(!s.apply(Action::Save));
    }

    #[test]
    fn pass_spp_doubles() {
        assert_eq!((0..5).map(pass_spp).collect::<Vec<_>>(), [1, 2, 4, 8, 16]);
    }
}
