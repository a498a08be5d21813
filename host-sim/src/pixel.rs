//! `picomis-sim render --pixel X,Y`: one pixel's estimate split by technique, for a student
//! debugging a weight: what the surface the camera sees emits, what light sampling and BSDF
//! sampling each added (their weighted contributions), how many of their samples found light,
//! and the mean MIS weight of those. The parts are the kernel's [`Estimate`] of the pixel, the
//! one the render writes there (`Renderer::render_pixel`), and add up to its value.

use picomis::{ControlVariate, Estimate, LightSelection, MisModel, RenderSettings, Rgb, TechniqueEstimate};

/// Parses `X,Y` (the value parser of `--pixel`).
pub fn parse(s: &str) -> Result<(u32, u32), String> {
    let bad = || "expected X,Y: two whole numbers from 0 (column, row from the top left)".to_string();
    let (x, y) = s.split_once(',').ok_or_else(bad)?;
    Ok((x.trim().parse().map_err(|_| bad())?, y.trim().parse().map_err(|_| bad())?))
}

/// `v` as the table prints it: the shortest decimal that reads back as the same `f32`
/// (in exponent form when very small or large).
pub fn value(v: f32) -> String {
    if v == 0.0 || (1e-4..1e7).contains(&v.abs()) { format!("{v}") } else { format!("{v:e}") }
}

/// The rows of the table under its header: `[part, samples, found, mean weight, red, green,
/// blue]`; `lights`: the scene's number of lights (a light sample of the selection `every` is
/// one sample of each).
fn rows(settings: &RenderSettings, lights: usize, e: &Estimate) -> Vec<[String; 7]> {
    let spp = settings.spp();
    let (n_light, n_bsdf) = settings.technique_samples();
    let n_light = if settings.light_selection() == LightSelection::Every {
        n_light.saturating_mul(u16::try_from(lights).unwrap_or(u16::MAX))
    } else {
        n_light
    };
    let one_sample = matches!(settings.mis_model(), MisModel::One { .. });
    let rgb = |c: Rgb| [value(c.x), value(c.y), value(c.z)];
    let technique = |name: &str, n: u16, t: &TechniqueEstimate| {
        let drawn = if one_sample { "-".to_string() } else { (u64::from(n) * u64::from(spp)).to_string() };
        let weight = if t.found > 0 { value(t.mean_weight()) } else { "-".to_string() };
        let [r, g, b] = rgb(t.contribution);
        [name.to_string(), drawn, t.found.to_string(), weight, r, g, b]
    };
    let [r, g, b] = rgb(e.emitted);
    let emitted = ["emitted".to_string(), spp.to_string(), "-".into(), "-".into(), r, g, b];
    let [r, g, b] = rgb(e.radiance());
    let pixel = ["pixel".to_string(), String::new(), String::new(), String::new(), r, g, b];
    vec![emitted, technique("light", n_light, &e.light), technique("bsdf", n_bsdf, &e.bsdf), pixel]
}

/// The breakdown of estimate `e` of a pixel rendered with `settings`, under `title`: a table
/// (one row per part and the pixel's value, `emitted + light + bsdf`), then what its columns
/// mean and what the settings change in it.
pub fn table(title: &str, settings: &RenderSettings, lights: usize, e: &Estimate) -> String {
    let header = ["part", "samples", "found", "mean weight", "red", "green", "blue"].map(String::from);
    let mut all = vec![header];
    all.extend(rows(settings, lights, e));
    let widths: Vec<usize> = (0..7).map(|c| all.iter().map(|r| r[c].len()).max().unwrap_or(0)).collect();
    let mut out = format!("{title}\n");
    for row in &all {
        let mut line = format!("{:<w$}", row[0], w = widths[0]);
        for (cell, &w) in row.iter().zip(&widths).skip(1) {
            line.push_str(&format!("  {cell:>w$}"));
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
    out.push_str(&format!(
        "samples: drawn in the {} camera samples; found: those that found light (a non-zero \
         integrand); mean weight: their mean MIS weight; red, green, blue: the part's mean \
         contribution; pixel = emitted + light + bsdf, the value in the image\n",
        settings.spp()
    ));
    if let MisModel::One { .. } = settings.mis_model() {
        out.push_str(&format!(
            "one-sample model: each camera sample draws one technique, light with probability {}\n",
            value(settings.c_light())
        ));
    }
    if settings.light_selection() == LightSelection::Every {
        out.push_str(&format!(
            "light selection every: each light sample is one sample of each of the scene's {lights} lights\n"
        ));
    }
    if settings.control_variate() != ControlVariate::Off {
        out.push_str(&format!(
            "control variate {}: the light part includes the unoccluded light in closed form (no samples)\n",
            picomis::Choice::name(settings.control_variate())
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_positions() {
        assert_eq!(parse("3,4"), Ok((3, 4)));
        assert_eq!(parse("3, 4"), Ok((3, 4)));
        for bad in ["3", "3,", "-1,2", "a,b", "1.5,2", "3;4"] {
            assert!(parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn values_read_back_exactly() {
        for v in [0.0, 1.0, 0.1, 1.0 / 3.0, 1e-5, 3.4e38, 12345.678, 1e-38] {
            assert_eq!(value(v).parse::<f32>().unwrap(), v, "{v} printed as {}", value(v));
        }
        assert_eq!(value(0.25), "0.25");
        assert_eq!(value(1e-5), "1e-5");
    }
}
