//! The film drawn tile by tile into a display (or a framebuffer), with progress after each row
//! of tiles.

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::Size;
use embedded_graphics_core::pixelcolor::Rgb888;
use picomis::{Integrator, RenderStats, Strategies};

/// How far [`draw`] is: passed to its callback after each row of tiles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Progress {
    /// Rows `0..rows` of the film are drawn.
    pub rows: u32,
    /// The film's height.
    pub height: u32,
    /// What the render did so far.
    pub stats: RenderStats,
}

/// Draws the whole film of `integrator`'s scene into `target` (whose pixel (0, 0) is the film's),
/// tile by tile with tiles of `tile` pixels, each tile's pixels as one `fill_contiguous` (one
/// address window on an SPI display). Calls `on_rows` after each row of tiles; with the `defmt`
/// feature also logs it at debug level. Passes the target's error through.
pub fn draw<St, const S: usize, const L: usize, const M: usize, D>(
    integrator: &Integrator<'_, St, S, L, M>,
    tile: Size,
    target: &mut D,
    mut on_rows: impl FnMut(&Progress),
) -> Result<RenderStats, D::Error>
where
    St: Strategies<L>,
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    let film = integrator.scene().film();
    let (width, height) = (film.width(), film.height());
    integrator.render(tile, target, |area, total| {
        // The tiles lie inside the film: their corners are non-negative.
        let right = area.top_left.x as u32 + area.size.width;
        if right >= width {
            let progress =
                Progress { rows: area.top_left.y as u32 + area.size.height, height, stats: *total };
            #[cfg(feature = "defmt")]
            defmt::debug!(
                "picomis: rows 0..{=u32} of {=u32} drawn, {=u64} camera samples",
                progress.rows,
                height,
                total.camera_samples
            );
            on_rows(&progress);
        }
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use std::vec;
    use std::vec::Vec;

    use embedded_graphics_core::Pixel;
    use embedded_graphics_core::geometry::{OriginDimensions, Size};
    use embedded_graphics_core::pixelcolor::Rgb888;
    use picomis::integrator::{control_variate, model};
    use picomis::light::{lobe, quad, select, sphere};
    use picomis::*;

    use super::*;

    /// The lecture's strategies (`Preset::Lecture`) for one light.
    type Lecture = Direct<
        Lights<select::Uniform, sphere::InCone, quad::ByArea, lobe::Off>,
        control_variate::Off,
        model::Multi,
    >;

    /// A floor lit by a sphere light on a 20 x 12 film.
    pub(crate) fn scene() -> Scene<2, 1, 2> {
        let camera = CameraDesc {
            origin: Vec3::new(0.0, 1.0, 4.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_deg: 40.0,
            fov_axis: FovAxis::Y,
            near_clip: 0.0,
        };
        let film = Film::new(20, 12).expect("film");
        let mut scene = Scene::new(camera, film).expect("camera");
        let white = scene.add_material(Material::lambertian(Rgb::splat(0.8)).expect("albedo")).expect("room");
        let black = scene.add_material(Material::lambertian(Rgb::ZERO).expect("albedo")).expect("room");
        let floor = [
            Vec3::new(-2.0, 0.0, 2.0),
            Vec3::new(2.0, 0.0, 2.0),
            Vec3::new(2.0, 0.0, -2.0),
            Vec3::new(-2.0, 0.0, -2.0),
        ];
        scene.add_shape(Shape::quad(floor).expect("quad"), white).expect("room");
        let bulb = scene
            .add_shape(Shape::sphere(Vec3::new(0.0, 1.5, 0.0), 0.25).expect("sphere"), black)
            .expect("room");
        scene.add_area_light(bulb, Rgb::splat(10.0)).expect("light");
        scene
    }

    /// A film-sized canvas that counts the writes of each pixel.
    struct Canvas {
        size: Size,
        pixels: Vec<(Rgb888, u32)>,
    }

    impl OriginDimensions for Canvas {
        fn size(&self) -> Size {
            self.size
        }
    }

    impl DrawTarget for Canvas {
        type Color = Rgb888;
        type Error = core::convert::Infallible;

        fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(&mut self, pixels: I) -> Result<(), Self::Error> {
            for Pixel(p, c) in pixels {
                let i = p.y as usize * self.size.width as usize + p.x as usize;
                self.pixels[i] = (c, self.pixels[i].1 + 1);
            }
            Ok(())
        }
    }

    #[test]
    fn draws_every_pixel_once_and_reports_each_row_of_tiles() {
        let scene = scene();
        let settings = Preset::Lecture.settings().with_spp(2).expect("spp").with_seed(3);
        let integrator =
            Integrator::<Lecture, 2, 1, 2>::new(&scene, &settings).expect("the lecture's strategies");
        let size = Size::new(20, 12);
        let mut canvas = Canvas { size, pixels: vec![(Rgb888::new(1, 2, 3), 0); 240] };
        let mut reports = Vec::new();
        let stats =
            draw(&integrator, Size::new(8, 8), &mut canvas, |p| reports.push(*p)).expect("infallible");

        assert_eq!(stats, RenderStats::new(240, 2));
        // Tiles of 8 x 8 on 20 x 12: two rows of three tiles, the last ones cut.
        assert_eq!(
            reports,
            [
                Progress { rows: 8, height: 12, stats: RenderStats::new(160, 2) },
                Progress { rows: 12, height: 12, stats: RenderStats::new(240, 2) },
            ]
        );
        for y in 0..12 {
            for x in 0..20 {
                let (color, writes) = canvas.pixels[(y * 20 + x) as usize];
                assert_eq!(writes, 1, "pixel ({x}, {y}) written {writes} times");
                assert_eq!(color, tone_map(integrator.render_pixel(x, y).radiance()), "pixel ({x}, {y})");
            }
        }
    }
}
