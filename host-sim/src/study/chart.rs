//! Log-log charts with plotters: one line per method, a band for the spread across seeds, PNG
//! (drawn into a buffer and encoded by [`crate::output::encode_png`]) and SVG. Text uses the
//! crate's embedded DejaVu Sans through plotters' `ab_glyph` backend, so no system font is needed.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use crate::SimError;
use crate::output::encode_png;

static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// Chart size in pixels.
pub const SIZE: (u32, u32) = (960, 640);

/// Registers the embedded font as plotters' "sans-serif".
pub fn register_font_once() -> Result<(), SimError> {
    register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| SimError::Io("embedded font DejaVuSans.ttf could not be registered".into()))
}

/// One point of a line: x, mean y, and the y range across seeds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// x (seconds or spp).
    pub x: f64,
    /// Mean error.
    pub y: f64,
    /// Smallest error across seeds.
    pub lo: f64,
    /// Largest error across seeds.
    pub hi: f64,
}

/// One line.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Colour.
    pub color: RGBColor,
    /// Dashed (the single techniques) or solid (the heuristics).
    pub dashed: bool,
    /// Points, by increasing x.
    pub points: Vec<Point>,
}

/// A chart.
#[derive(Clone, Debug)]
pub struct Chart {
    /// Title.
    pub title: String,
    /// x-axis label.
    pub x_desc: String,
    /// y-axis label.
    pub y_desc: String,
    /// Lines.
    pub series: Vec<Series>,
    /// A horizontal reference line (label, y), e.g. the reference's own noise.
    pub floor: Option<(String, f64)>,
}

/// Okabe-Ito colours (distinguishable with colour-blindness), one per study method.
pub const COLORS: [RGBColor; 15] = [
    RGBColor(213, 94, 0),    // bsdf: vermillion
    RGBColor(86, 180, 233),  // light (area): sky blue
    RGBColor(0, 114, 178),   // light (cone): blue
    RGBColor(230, 159, 0),   // average: orange
    RGBColor(0, 0, 0),       // balance: black
    RGBColor(0, 158, 115),   // power: bluish green
    RGBColor(204, 121, 167), // maximum: reddish purple
    RGBColor(128, 128, 128), // cutoff: grey
    RGBColor(136, 34, 85),   // power, independent: wine
    RGBColor(153, 153, 51),  // power, lights by power: olive
    RGBColor(221, 51, 51),   // power, lights by contribution: red
    RGBColor(0, 68, 136),    // power, lobe mixing: dark blue
    RGBColor(51, 34, 136),   // one-sample: indigo
    RGBColor(68, 170, 153),  // quads by solid angle: teal
    RGBColor(170, 68, 153),  // control variate: purple
];

/// A tick label for the log axes: only at 1, 2 and 5 times a power of ten (others are blank).
fn tick(v: f64) -> String {
    if !(v > 0.0 && v.is_finite()) {
        return String::new();
    }
    let exp = v.log10().floor();
    let mantissa = v / 10f64.powf(exp);
    let m = mantissa.round();
    if (mantissa - m).abs() > 1e-6 * mantissa || ![1.0, 2.0, 5.0].contains(&m) {
        return String::new();
    }
    if (1e-2..1e4).contains(&v) {
        let s = format!("{v:.2}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{m}e{exp}")
    }
}

fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if lo > hi { (0.1, 10.0) } else { (lo / 1.5, hi * 1.5) }
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, c: &Chart) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let (x0, x1) = range(c.series.iter().flat_map(|s| s.points.iter().map(|p| p.x)));
    let (y0, y1) = range(
        c.series
            .iter()
            .flat_map(|s| s.points.iter().flat_map(|p| [p.lo, p.hi]))
            .chain(c.floor.iter().map(|f| f.1)),
    );
    let mut chart = ChartBuilder::on(root)
        .caption(&c.title, ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(46)
        .y_label_area_size(72)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(&c.x_desc)
        .y_desc(&c.y_desc)
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .map_err(e)?;
    if let Some((label, y)) = &c.floor {
        let grey = RGBColor(150, 150, 150);
        chart
            .draw_series(DashedLineSeries::new([(x0, *y), (x1, *y)], 2, 4, grey.stroke_width(1)))
            .map_err(e)?
            .label(label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], grey.stroke_width(1)));
    }
    for s in &c.series {
        let color = s.color;
        if s.points.len() > 1 {
            let band: Vec<(f64, f64)> = s
                .points
                .iter()
                .map(|p| (p.x, p.hi))
                .chain(s.points.iter().rev().map(|p| (p.x, p.lo.max(y0))))
                .collect();
            chart.draw_series(std::iter::once(Polygon::new(band, color.mix(0.14).filled()))).map_err(e)?;
        }
        let line: Vec<(f64, f64)> = s.points.iter().map(|p| (p.x, p.y)).collect();
        let style = color.stroke_width(2);
        let anno = if s.dashed {
            chart.draw_series(DashedLineSeries::new(line.clone(), 8, 5, style)).map_err(e)?
        } else {
            chart.draw_series(LineSeries::new(line.clone(), style)).map_err(e)?
        };
        anno.label(s.label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(2)));
        chart.draw_series(line.iter().map(|&p| Circle::new(p, 3, color.filled()))).map_err(e)?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .label_font(("sans-serif", 15))
        .background_style(WHITE.mix(0.88))
        .border_style(RGBColor(160, 160, 160))
        .draw()
        .map_err(e)?;
    root.present().map_err(e)?;
    Ok(())
}

/// The chart as PNG bytes and SVG text.
pub fn render(c: &Chart) -> Result<(Vec<u8>, String), SimError> {
    let (w, h) = SIZE;
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        draw(&root, c).map_err(|m| SimError::Io(format!("chart {}: {m}", c.title)))?;
    }
    let png = encode_png(w, h, &buf).map_err(SimError::Io)?;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
        draw(&root, c).map_err(|m| SimError::Io(format!("chart {}: {m}", c.title)))?;
    }
    Ok((png, svg))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_short() {
        assert_eq!(tick(0.5), "0.5");
        assert_eq!(tick(20.0), "20");
        assert_eq!(tick(1e-4), "1e-4");
        assert_eq!(tick(0.001), "1e-3");
        assert_eq!(tick(0.002), "2e-3");
        assert_eq!(tick(0.07), "");
        assert_eq!(tick(0.05), "0.05");
        assert_eq!(tick(3e5), "");
    }
}
