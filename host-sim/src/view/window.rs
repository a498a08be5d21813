//! The window of `picomis-sim view` (feature `window`): an `embedded-graphics-simulator`
//! `SimulatorDisplay<Rgb565>` the size of the panel plus a status bar, refreshed while the
//! kernel renders into it tile by tile; keys switch method, view and sampling.
//!
//! With `EG_SIMULATOR_DUMP` (or the simulator's other `EG_SIMULATOR_*` variables) set, the
//! window is updated only once, after the last pass: the simulator then writes the display to
//! that PNG and exits, a second check of what the window shows.

use std::time::{Duration, Instant};

use embedded_graphics::mono_font::MonoTextStyle;
use embedded_graphics::mono_font::ascii::FONT_6X10;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::{PrimitiveStyle, Rectangle};
use embedded_graphics::text::{Baseline, Text};
use embedded_graphics_simulator::sdl2::{Keycode, Mod};
use embedded_graphics_simulator::{OutputSettingsBuilder, SimulatorDisplay, SimulatorEvent, Window};
use picomis::Film;
use picomis_host::HostScene;

use super::{Action, KEYS, STATUS_HEIGHT, ViewArgs, ViewState, pass_spp, render_pass};
use crate::SimError;
use crate::output::{encode_png, write_atomic};
use crate::scenes::Loaded;

/// Shortest time between two window refreshes while a pass renders.
const REFRESH: Duration = Duration::from_millis(30);

/// Runs the window until it is closed.
pub fn run(loaded: &Loaded, film: Film, state: ViewState, args: &ViewArgs) -> Result<(), SimError> {
    let name = loaded.file.name().to_string();
    let scene = loaded.build(film)?;
    window_loop(&scene, state, args, &name)
}

/// Why a pass stopped early: a key changed what is shown, or the window was closed.
#[derive(Debug)]
struct Interrupted;

/// The simulator's display as the kernel's `DrawTarget`: each tile goes into the display, the
/// window is refreshed at most every [`REFRESH`], and keys are read between tiles.
struct Live<'a> {
    display: &'a mut SimulatorDisplay<Rgb565>,
    window: &'a mut Window,
    film: Size,
    live: bool,
    last_refresh: Instant,
    actions: Vec<Action>,
}

impl Live<'_> {
    /// Refreshes the window and reads keys; true if one of them asks for a new render.
    fn poll(&mut self, force: bool) -> bool {
        if !self.live || !(force || self.last_refresh.elapsed() >= REFRESH) {
            return false;
        }
        self.window.update(self.display);
        self.last_refresh = Instant::now();
        let mut interrupt = false;
        for event in self.window.events() {
            let action = match event {
                SimulatorEvent::Quit => Some(Action::Quit),
                SimulatorEvent::KeyDown { keycode, keymod, .. } => key_action(keycode, keymod),
                _ => None,
            };
            if let Some(a) = action {
                interrupt |= a != Action::Save;
                self.actions.push(a);
            }
        }
        interrupt
    }
}

impl OriginDimensions for Live<'_> {
    fn size(&self) -> Size {
        self.film
    }
}

impl DrawTarget for Live<'_> {
    type Color = Rgb565;
    type Error = Interrupted;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(&mut self, pixels: I) -> Result<(), Interrupted> {
        let Ok(()) = self.display.draw_iter(pixels);
        Ok(())
    }

    fn fill_contiguous<I: IntoIterator<Item = Rgb565>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), Interrupted> {
        let Ok(()) = self.display.fill_contiguous(area, colors);
        if self.poll(false) { Err(Interrupted) } else { Ok(()) }
    }
}

fn key_action(key: Keycode, keymod: Mod) -> Option<Action> {
    let shift = keymod.intersects(Mod::LSHIFTMOD | Mod::RSHIFTMOD);
    let d = if shift { -1 } else { 1 };
    Some(match key {
        Keycode::M => Action::Method(d),
        Keycode::V => Action::View(d),
        Keycode::B => Action::Beta(d),
        Keycode::A => Action::Alpha(d),
        Keycode::L => Action::LightSelection,
        Keycode::S => Action::SphereSampling,
        Keycode::G => Action::LobeMixing,
        Keycode::P => Action::Save,
        Keycode::Q | Keycode::ESCAPE => Action::Quit,
        _ => return None,
    })
}

/// Draws the three status lines under the image.
fn draw_status(display: &mut SimulatorDisplay<Rgb565>, film: Size, lines: [&str; 3]) {
    let bar = Rectangle::new(Point::new(0, film.height as i32), Size::new(film.width, STATUS_HEIGHT));
    let background = Rgb565::new(3, 6, 3);
    let Ok(()) = bar.into_styled(PrimitiveStyle::with_fill(background)).draw(display);
    let style = MonoTextStyle::new(&FONT_6X10, Rgb565::WHITE);
    for (i, line) in lines.iter().enumerate() {
        let at = Point::new(2, film.height as i32 + 1 + 10 * i as i32);
        let Ok(_) = Text::with_baseline(line, at, style, Baseline::Top).draw(display);
    }
}

/// The film area of the display as 8-bit RGB, converted the way the simulator converts it.
fn film_rgb(display: &SimulatorDisplay<Rgb565>, film: Size) -> Vec<u8> {
    let mut out = Vec::with_capacity((film.width * film.height * 3) as usize);
    for y in 0..film.height as i32 {
        for x in 0..film.width as i32 {
            let c: Rgb888 = display.get_pixel(Point::new(x, y)).into();
            out.extend_from_slice(&[c.r(), c.g(), c.b()]);
        }
    }
    out
}

/// Shows `scene` pass by pass, and applies the keys, until the window is closed.
fn window_loop(scene: &HostScene, mut state: ViewState, args: &ViewArgs, name: &str) -> Result<(), SimError> {
    let film = Size::new(scene.film().width(), scene.film().height());
    let mut display = SimulatorDisplay::<Rgb565>::new(Size::new(film.width, film.height + STATUS_HEIGHT));
    let settings = OutputSettingsBuilder::new().scale(args.scale).build();
    let title = format!("picomis: {name} ({}x{} Rgb565)", film.width, film.height);
    let mut window = Window::new(&title, &settings);
    window.set_max_fps(1000);
    let dump = std::env::vars_os().any(|(k, _)| k.to_string_lossy().starts_with("EG_SIMULATOR_"));
    println!("{title}: {KEYS}");

    // The last complete pass, for `p`.
    let mut last: Option<(Vec<u8>, String)> = None;
    let mut pass = 0u32;
    let mut pass_ms = 0.0;
    let mut live = Live {
        display: &mut display,
        window: &mut window,
        film,
        live: !dump,
        last_refresh: Instant::now(),
        actions: Vec::new(),
    };
    loop {
        let method = state.method_label();
        let sampling = state.sampling_label();
        if pass < args.passes {
            let spp = pass_spp(pass);
            let settings = state.settings(spp).map_err(SimError::Usage)?;
            let renderer = picomis_host::renderer(scene, &settings)
                .map_err(|e| SimError::Usage(format!("{name}: {e}")))?;
            let done = if pass == 0 { "-".to_string() } else { format!("{} spp", pass_spp(pass - 1)) };
            let status = format!("{done}, rendering {spp}");
            draw_status(
                live.display,
                film,
                [&method, &format!("{}, {sampling}", state.view.label()), &status],
            );
            live.poll(true);
            let start = Instant::now();
            if render_pass(&*renderer, scene.film(), state.view, args.tile, &mut live).is_ok() {
                pass_ms = start.elapsed().as_secs_f64() * 1e3;
                pass += 1;
                let status = format!("{spp} spp, {pass_ms:.0} ms/pass");
                draw_status(
                    live.display,
                    film,
                    [&method, &format!("{}, {sampling}", state.view.label()), &status],
                );
                last = Some((film_rgb(live.display, film), format!("{spp}spp")));
                if pass == args.passes && !live.live {
                    // Dump mode: one update, after the last pass; the simulator writes the
                    // PNG and exits the process.
                    live.window.update(live.display);
                    return Ok(());
                }
                live.poll(true);
                // After the window shows it (tests/window.rs waits for this line).
                println!(
                    "pass {pass}: {spp} spp, {pass_ms:.1} ms, {method}, {}, {sampling}",
                    state.view.label()
                );
            }
        } else {
            let status = format!("{} spp, {pass_ms:.0} ms/pass, done", pass_spp(pass - 1));
            draw_status(
                live.display,
                film,
                [&method, &format!("{}, {sampling}", state.view.label()), &status],
            );
            std::thread::sleep(Duration::from_millis(20));
            live.poll(true);
        }
        for action in std::mem::take(&mut live.actions) {
            match action {
                Action::Quit => return Ok(()),
                Action::Save => {
                    let Some((rgb, spp)) = &last else { continue };
                    let view = state.view.label().replace(' ', "_");
                    let file = format!("{name}_{}_{view}_{spp}.png", super::method_name_at(state.method));
                    let png = encode_png(film.width, film.height, rgb).map_err(SimError::Io)?;
                    write_atomic(std::path::Path::new(&file), &png).map_err(SimError::Io)?;
                    println!("saved {file}");
                }
                other => {
                    if state.apply(other) {
                        pass = 0;
                    }
                }
            }
        }
    }
}
