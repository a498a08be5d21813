//! Property 3: an image depends only on the seed, whatever the order of its pixels and tiles and
//! the number of threads, through `render_pixel` and through the `DrawTarget` paths.

use crate::runner::{Tally, check_property, estimator};
use crate::scenes::{S, build, scene_spec, settings};
use embedded_graphics_core::Pixel;
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{OriginDimensions, Size};
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};
use embedded_graphics_core::primitives::{PointsIter, Rectangle};
use picomis::integrator::{control_variate, model};
use picomis::light::LightStrategies;
use picomis::{Direct, Estimate, Film, Integrator, RenderSettings, Rgb, Sampler, tiles, tone_map};
use picomis_host::{HOST_LIGHTS, HOST_MATERIALS, HOST_SHAPES, Renderer};
use picomis_tests::{LightChoices, VisitLights};
use proptest::prelude::*;
use proptest::test_runner::TestCaseResult;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

const W: u32 = 12;
const H: u32 = 8;

/// Every field of an estimate, as bits.
fn bits(e: &Estimate) -> [u32; 13] {
    let c = |v: Rgb| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
    let (em, l, b) = (c(e.emitted), c(e.light.contribution), c(e.bsdf.contribution));
    [
        em[0],
        em[1],
        em[2],
        l[0],
        l[1],
        l[2],
        e.light.weight_sum.to_bits(),
        e.light.found,
        b[0],
        b[1],
        b[2],
        e.bsdf.weight_sum.to_bits(),
        e.bsdf.found,
    ]
}

type Image = Vec<[u32; 13]>;

fn pixel_bits(it: &dyn Renderer, i: u32) -> [u32; 13] {
    bits(&it.render_pixel(i % W, i / W))
}

/// Renders pixel indices in `order` into a row-major image.
fn render_in_order(it: &dyn Renderer, order: impl Iterator<Item = u32>) -> Image {
    let mut img = vec![[0; 13]; (W * H) as usize];
    for i in order {
        img[i as usize] = pixel_bits(it, i);
    }
    img
}

/// A permutation of 0..n from `seed` (Fisher-Yates on the kernel's own generator).
fn shuffled(n: usize, seed: u32) -> Vec<usize> {
    let mut v: Vec<usize> = (0..n).collect();
    let mut rng = Sampler::new(seed, 0x5AFF, 0);
    for i in (1..n).rev() {
        let j = (rng.next_u32() as usize) % (i + 1);
        v.swap(i, j);
    }
    v
}

/// Pixel indices of the tiles of `tile` pixels, tiles in a shuffled order.
fn tile_order(tile: Size, seed: u32) -> Vec<u32> {
    let all: Vec<Rectangle> = tiles(Film::new(W, H).unwrap(), tile).collect();
    let mut out = Vec::new();
    for t in shuffled(all.len(), seed) {
        let r = all[t];
        for y in r.rows() {
            for x in r.columns() {
                out.push(y as u32 * W + x as u32);
            }
        }
    }
    out
}

/// `threads` threads take the work items `0..jobs` as they come; `work` returns the pixels it
/// rendered. The merged image does not depend on which thread took which item.
fn render_threaded(
    threads: usize,
    jobs: usize,
    work: impl Fn(usize) -> Vec<(u32, [u32; 13])> + Sync,
) -> Image {
    let next = AtomicUsize::new(0);
    let img = Mutex::new(vec![[0; 13]; (W * H) as usize]);
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| {
                loop {
                    let job = next.fetch_add(1, Ordering::Relaxed);
                    if job >= jobs {
                        break;
                    }
                    let done = work(job);
                    let mut img = img.lock().unwrap();
                    for (i, b) in done {
                        img[i as usize] = b;
                    }
                }
            });
        }
    });
    img.into_inner().unwrap()
}

/// A framebuffer of tone-mapped pixels (the host's stand-in for a display), any size.
struct Framebuffer {
    area: Rectangle,
    pixels: Vec<Rgb888>,
}

impl Framebuffer {
    fn new(area: Rectangle) -> Self {
        Self { area, pixels: vec![Rgb888::new(1, 2, 3); (area.size.width * area.size.height) as usize] }
    }

    fn bytes(&self) -> Vec<u8> {
        self.pixels.iter().flat_map(|c| [c.r(), c.g(), c.b()]).collect()
    }
}

impl OriginDimensions for Framebuffer {
    fn size(&self) -> Size {
        self.area.size
    }
}

impl DrawTarget for Framebuffer {
    type Color = Rgb888;
    type Error = core::convert::Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(&mut self, pixels: I) -> Result<(), Self::Error> {
        for Pixel(p, c) in pixels {
            let (x, y) = (p.x - self.area.top_left.x, p.y - self.area.top_left.y);
            let w = self.area.size.width as i32;
            if (0..w).contains(&x) && (0..self.area.size.height as i32).contains(&y) {
                self.pixels[(y * w + x) as usize] = c;
            }
        }
        Ok(())
    }
}

fn check_determinism(scene: &S, settings: &RenderSettings, tile: Size, seed: u32) -> TestCaseResult {
    let n = W * H;
    let it = &*estimator(scene, settings)?;
    let reference = render_in_order(it, 0..n);
    let mut variants = vec![
        ("reverse order".to_string(), render_in_order(it, (0..n).rev())),
        (format!("shuffled {tile:?} tiles"), render_in_order(it, tile_order(tile, seed).into_iter())),
    ];
    let order = shuffled(n as usize, seed);
    for threads in [2, 3, 4] {
        let per_pixel = render_threaded(threads, n as usize, |j| {
            let i = order[j] as u32;
            vec![(i, pixel_bits(it, i))]
        });
        variants.push((format!("{threads} threads, shuffled pixels"), per_pixel));
        let all: Vec<Rectangle> = tiles(scene.film(), tile).collect();
        let per_tile = render_threaded(threads, all.len(), |j| {
            let r = all[j];
            r.rows()
                .flat_map(|y| r.columns().map(move |x| y as u32 * W + x as u32))
                .map(|i| (i, pixel_bits(it, i)))
                .collect()
        });
        variants.push((format!("{threads} threads, {tile:?} tiles"), per_tile));
    }
    for (name, img) in &variants {
        if let Some(i) = (0..n as usize).find(|&i| img[i] != reference[i]) {
            prop_assert!(
                false,
                "{name}: pixel ({}, {}) differs: {:?} vs {:?}",
                i as u32 % W,
                i as u32 / W,
                img[i],
                reference[i]
            );
        }
    }

    // The same through the DrawTarget path of the estimator of the settings' strategies.
    LightChoices::of(settings).visit(DrawPaths { scene, settings, tile, seed })
}

/// The DrawTarget path of [`check_determinism`], through the estimator of the light strategies
/// `Lt`, without the control variate, in the multi-sample model (what [`settings`] draws).
struct DrawPaths<'a> {
    scene: &'a S,
    settings: &'a RenderSettings,
    tile: Size,
    seed: u32,
}

/// The estimator of the light strategies `Lt`, without the control variate, in the multi-sample
/// model.
type DrawIntegrator<'a, Lt> =
    Integrator<'a, Direct<Lt, control_variate::Off, model::Multi>, HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS>;

impl VisitLights<HOST_LIGHTS> for DrawPaths<'_> {
    type Output = TestCaseResult;
    fn visit<Lt: LightStrategies<HOST_LIGHTS>>(self) -> TestCaseResult {
        let (scene, settings) = (self.scene, self.settings);
        let it = DrawIntegrator::<Lt>::new(scene, settings)
            .map_err(|e| TestCaseError::fail(format!("{settings:?}: {e}")))?;
        check_draw_paths(&it, self.tile, self.seed)
    }
}

/// `render` in row-major tiles, and `render_tile` per shuffled tile on 3 threads, each into its
/// own framebuffer, copied into one: the same bytes, and those of `tone_map` of the pixels.
fn check_draw_paths<Lt: LightStrategies<HOST_LIGHTS>>(
    it: &DrawIntegrator<'_, Lt>,
    tile: Size,
    seed: u32,
) -> TestCaseResult {
    let (n, scene) = (W * H, it.scene());
    let full = Rectangle::new(embedded_graphics_core::geometry::Point::zero(), Size::new(W, H));
    let mut whole = Framebuffer::new(full);
    let stats = it.render(tile, &mut whole, |_, _| {}).unwrap();
    prop_assert_eq!(stats.pixels, n);
    let mapped: Vec<u8> = (0..n)
        .flat_map(|i| {
            let c = tone_map(it.render_pixel(i % W, i / W).radiance());
            [c.r(), c.g(), c.b()]
        })
        .collect();
    prop_assert!(whole.bytes() == mapped, "render() differs from tone_map(render_pixel)");
    let all: Vec<Rectangle> = tiles(scene.film(), tile).collect();
    let order = shuffled(all.len(), seed ^ 1);
    let parts = Mutex::new(Vec::new());
    let next = AtomicUsize::new(0);
    std::thread::scope(|s| {
        for _ in 0..3 {
            s.spawn(|| {
                loop {
                    let j = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&t) = order.get(j) else { break };
                    let mut fb = Framebuffer::new(all[t]);
                    it.render_tile(&all[t], &mut fb).unwrap();
                    parts.lock().unwrap().push(fb);
                }
            });
        }
    });
    let mut merged = Framebuffer::new(full);
    for fb in parts.into_inner().unwrap() {
        let pixels = fb.area.points().zip(fb.pixels.iter().copied()).map(|(p, c)| Pixel(p, c));
        merged.draw_iter(pixels).unwrap();
    }
    prop_assert!(merged.bytes() == whole.bytes(), "render_tile on 3 threads differs from render()");
    Ok(())
}

#[test]
fn images_depend_only_on_the_seed() {
    let tally = Tally::default();
    let tile = (1u32..=7, 1u32..=5).prop_map(|(w, h)| Size::new(w, h));
    check_property(64, (scene_spec(), settings(), tile, any::<u32>()), |(spec, settings, tile, seed)| {
        let Some(scene) = build(&spec, W, H) else { return Ok(()) };
        let it = estimator(&scene, &settings)?;
        let lit = (0..W * H).filter(|&i| it.render_pixel(i % W, i / W).radiance().max_element() > 0.0);
        if lit.count() > 10 {
            tally.add("image with more than 10 lit pixels");
        }
        check_determinism(&scene, &settings, tile, seed)
    });
    tally.require(&[("image with more than 10 lit pixels", 15)]);
}
