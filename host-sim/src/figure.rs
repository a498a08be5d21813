//! The lecture's MIS figure as one labelled PNG: each technique alone, the arithmetic
//! average, the balance, power and maximum heuristics, then the balance render's per-technique
//! MIS weights (false colour with a legend) and weighted contributions.

use embedded_graphics_core::pixelcolor::RgbColor;
use picomis::{Estimate, Heuristic, Method, Preset, RenderSettings, Rgb, TechniqueEstimate, tone_map};
use picomis_format::IntegratorDesc;

use crate::SimError;
use crate::render::{Batch, Estimates, RenderBatch};
use crate::scenes::Loaded;
use crate::text::{Canvas, draw_text, text_width};

/// The renders of the figure: the kernel's method name (default parameters) and panel label.
pub const METHODS: [(&str, &str); 6] = [
    ("bsdf", "(a) BSDF sampling alone"),
    ("light", "(b) light sampling alone"),
    ("average", "(c) arithmetic average"),
    ("balance", "(d) balance heuristic"),
    ("power", "(e) power heuristic, \u{3b2} = 2"),
    ("maximum", "(f) maximum heuristic"),
];

/// The method whose weights and contributions are shown.
const WEIGHTS_OF: Method = Method::Mis(Heuristic::Balance);

/// Index in [`METHODS`] of [`WEIGHTS_OF`]'s render.
fn weights_panel() -> usize {
    METHODS.iter().position(|(name, _)| *name == WEIGHTS_OF.name()).unwrap_or(0)
}

/// The figure's methods, from the kernel's names.
fn methods() -> Result<Vec<Method>, SimError> {
    METHODS
        .iter()
        .map(|(name, _)| {
            Method::from_name(name).ok_or_else(|| SimError::Usage(format!("unknown method {name:?}")))
        })
        .collect()
}

const BACKGROUND: [u8; 3] = [255, 255, 255];
const INK: [u8; 3] = [20, 20, 20];
const MUTED: [u8; 3] = [90, 90, 90];
const MARGIN: u32 = 14;
const LABEL: u32 = 28;
const LABEL_SIZE: f32 = 18.0;
const MIN_PANEL_WIDTH: u32 = 300;

/// Weight-image colour of pixels where no sample of the technique found light
/// ([`picomis_host::NO_LIGHT`]).
pub fn no_light() -> [u8; 3] {
    let c = picomis_host::NO_LIGHT;
    [c.r(), c.g(), c.b()]
}

/// False colour of a weight in [0, 1] ([`picomis_host::weight_color`]: viridis).
pub fn weight_color(w: f32) -> [u8; 3] {
    let c = picomis_host::weight_color(w);
    [c.r(), c.g(), c.b()]
}

/// The weight images' colour of one pixel: its technique's mean MIS weight over the samples
/// that found light, in false colour, or [`no_light`] where none did.
pub fn weight(t: &TechniqueEstimate) -> [u8; 3] {
    if t.found > 0 { weight_color(t.mean_weight()) } else { no_light() }
}

/// The contribution images' colour of one pixel: tone-mapped like the renders.
pub fn srgb(c: Rgb) -> [u8; 3] {
    let t = tone_map(c);
    [t.r(), t.g(), t.b()]
}

/// One panel's pixels at film resolution.
fn panel(img: &Estimates, f: impl Fn(&Estimate) -> [u8; 3]) -> Vec<[u8; 3]> {
    img.pixels.iter().map(f).collect()
}

/// Nearest-neighbour upscale by an integer factor.
fn upscale(src: &[[u8; 3]], w: u32, h: u32, k: u32) -> Vec<[u8; 3]> {
    let mut out = Vec::with_capacity((w * h * k * k) as usize);
    for y in 0..h * k {
        for x in 0..w * k {
            out.push(src[((y / k) * w + x / k) as usize]);
        }
    }
    out
}

/// The settings of the figure's renders for `loaded`'s scene: the scene file's integrator block
/// over the lecture's preset, `flags` over both, each panel with its own method (and at least one
/// light and one BSDF sample). A panel whose method has no light technique leaves the control
/// variate off (it belongs to that technique).
pub fn figure_settings(
    loaded: &Loaded,
    spp: u32,
    seed: u32,
    flags: &IntegratorDesc,
) -> Result<Vec<RenderSettings>, SimError> {
    for (set, flag) in
        [(flags.mis.is_some(), "--mis"), (flags.beta.is_some(), "--beta"), (flags.alpha.is_some(), "--alpha")]
    {
        if set {
            return Err(SimError::Usage(format!(
                "{flag}: the figure renders its own methods (one per panel)"
            )));
        }
    }
    let keys = crate::integrator::keys(loaded, flags, Some(Preset::Lecture));
    let (n_light, n_bsdf) =
        crate::integrator::integrator(loaded, flags, Some(Preset::Lecture), spp, seed)?.sample_counts();
    // Every panel draws from both techniques: its weights are the ones of the figure's methods.
    let keys =
        IntegratorDesc { light_samples: Some(n_light.max(1)), bsdf_samples: Some(n_bsdf.max(1)), ..keys };
    methods()?
        .into_iter()
        .map(|method| {
            let keys = crate::integrator::with_method(&keys, method);
            // A control variate named for the figure is for the panels with light samples.
            keys.settings(spp, seed)
                .or_else(|_| IntegratorDesc { control_variate: None, ..keys }.settings(spp, seed))
                .map_err(|e| SimError::Usage(format!("settings: {e}")))
        })
        .collect()
}

/// Renders the figure's six images of `loaded`'s scene at `spp` and composes the figure.
pub fn render_figure(
    loaded: &Loaded,
    spp: u32,
    seed: u32,
    flags: &IntegratorDesc,
) -> Result<(Canvas, Batch), SimError> {
    let settings = figure_settings(loaded, spp, seed, flags)?;
    let film = loaded.file.film();
    let scene = loaded.build(film)?;
    let batch = RenderBatch { settings: &settings, message: "figure" }
        .run(&scene)
        .map_err(|e| SimError::Usage(format!("{}: {e}", loaded.file.name())))?;
    let (n_light, n_bsdf) = settings[weights_panel()].technique_samples();
    let lights = loaded.file.counts().lights;
    let mut caption = vec![
        format!(
            "{}: {}x{}, {spp} camera samples per pixel, each with {n_light} light + {n_bsdf} BSDF sample{}, seed {seed}",
            loaded.file.name(),
            film.width(),
            film.height(),
            if n_bsdf == 1 { "" } else { "s" },
        ),
        if lights == 1 {
            "Light sampling samples the scene's one light; sphere lights are sampled in the cone they subtend.".to_string()
        } else {
            format!(
                "A light sample picks one of the {lights} lights uniformly; sphere lights are sampled in the cone they subtend."
            )
        },
    ];
    let beyond = IntegratorDesc::differences(&settings[weights_panel()], Preset::Lecture);
    if !beyond.is_empty() {
        let list: Vec<String> = beyond.iter().map(|(k, v)| format!("{k} {v}")).collect();
        caption.push(format!("Every render: {}.", list.join(", ")));
    }
    Ok((compose(&batch.images, &caption), batch))
}

/// Lays out the figure from the six renders of [`METHODS`] (same film).
pub fn compose(images: &[Estimates], caption: &[String]) -> Canvas {
    let (w, h) = (images[0].width, images[0].height);
    let k = MIN_PANEL_WIDTH.div_ceil(w).max(1);
    let (pw, ph) = (w * k, h * k);
    let columns = 4;
    let title_h = 96;
    let row_h = LABEL + ph + MARGIN;
    let width = columns * pw + (columns + 1) * MARGIN;
    let height = title_h + 3 * row_h + 10;
    let mut canvas = Canvas::new(width, height, BACKGROUND);

    draw_text(&mut canvas, MARGIN as f32, 10.0, 26.0, "Multiple importance sampling: direct lighting", INK);
    for (i, line) in caption.iter().enumerate() {
        draw_text(&mut canvas, MARGIN as f32, 44.0 + 22.0 * i as f32, 17.0, line, MUTED);
    }

    let put_panel = |canvas: &mut Canvas, row: u32, col: u32, label: &str, pixels: Vec<[u8; 3]>| {
        let x = MARGIN + col * (pw + MARGIN);
        let y = title_h + row * row_h;
        draw_text(canvas, x as f32, y as f32 + 3.0, LABEL_SIZE, label, INK);
        canvas.blit(i64::from(x), i64::from(y + LABEL), pw, ph, &upscale(&pixels, w, h, k));
    };

    for (i, (img, (_, label))) in images.iter().zip(METHODS).enumerate() {
        let (row, col) = if i < 4 { (0, i as u32) } else { (1, i as u32 - 4) };
        put_panel(&mut canvas, row, col, label, panel(img, |e| srgb(e.radiance())));
    }
    let balance = &images[weights_panel()];
    put_panel(&mut canvas, 1, 2, "(g) weight of BSDF samples in (d)", panel(balance, |e| weight(&e.bsdf)));
    put_panel(&mut canvas, 1, 3, "(h) weight of light samples in (d)", panel(balance, |e| weight(&e.light)));
    put_panel(
        &mut canvas,
        2,
        0,
        "(i) BSDF samples' contribution to (d)",
        panel(balance, |e| srgb(e.bsdf.contribution)),
    );
    put_panel(
        &mut canvas,
        2,
        1,
        "(j) light samples' contribution to (d)",
        panel(balance, |e| srgb(e.light.contribution)),
    );

    // Legend and reading guide in the last two cells.
    let x0 = MARGIN + 2 * (pw + MARGIN);
    let y0 = title_h + 2 * row_h;
    legend(&mut canvas, x0, y0, 2 * pw + MARGIN);
    canvas
}

fn legend(canvas: &mut Canvas, x0: u32, y0: u32, width: u32) {
    let (x0f, y0f) = (x0 as f32, y0 as f32);
    draw_text(
        canvas,
        x0f,
        y0f + 3.0,
        LABEL_SIZE,
        "MIS weight, (g) and (h): mean over the samples that found light",
        INK,
    );
    let bar_w = width.min(520) - 40;
    let (bx, by, bh) = (x0 + 10, y0 + LABEL + 8, 22);
    for i in 0..bar_w {
        let c = weight_color(i as f32 / (bar_w - 1) as f32);
        canvas.fill(i64::from(bx + i), i64::from(by), 1, bh, c);
    }
    for t in 0..=4 {
        let v = t as f32 / 4.0;
        let tx = bx as f32 + v * (bar_w - 1) as f32;
        canvas.fill(tx as i64, i64::from(by + bh), 1, 6, INK);
        let s = format!("{v}");
        let tw = text_width(&s, 15.0);
        draw_text(canvas, tx - tw / 2.0, (by + bh + 7) as f32, 15.0, &s, INK);
    }
    let gy = by + bh + 34;
    canvas.fill(i64::from(bx), i64::from(gy), 22, 18, no_light());
    draw_text(canvas, (bx + 30) as f32, gy as f32, 15.0, "no sample of that technique found light", INK);

    let notes = [
        "Each technique fails somewhere: BSDF sampling on small lights seen",
        "in rough surfaces, light sampling on big lights seen in smooth ones.",
        "(c) w = 1/2 keeps the noise of both (a) and (b).",
        "(d) w_i = n_i p_i / \u{3a3}_k n_k p_k: good everywhere; (e), (f) are close.",
        "(i) + (j) + emitted light = (d).",
    ];
    let mut y = (gy + 34) as f32;
    for line in notes {
        draw_text(canvas, (bx - 10) as f32, y, 16.0, line, INK);
        y += 22.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_weights_shown_are_balances() {
        assert_eq!(methods().unwrap()[weights_panel()], WEIGHTS_OF);
    }
}
