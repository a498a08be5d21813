//! Which objects a camera ray can hit, tile by tile of the film. The camera is a pinhole and
//! the scene does not move, so where each object can appear on the film is known when the
//! scene is built: a camera ray through a tile that an object's image misses cannot hit the
//! object, and the camera's ray query skips it ([`Scene::intersect_camera`]). The nearest hit
//! is the same, bit for bit: only objects that no ray through the tile hits are skipped, and
//! the rest are tested as before, in the same order.
//!
//! The film is cut into [`COLUMNS`] x [`ROWS`] tiles. Each tile keeps a bit mask of the objects
//! whose image overlaps it; objects from index [`CULLED`] on are always tested. An object's
//! image is bounded in the camera's view coordinates (x right, y up, z forward), where a point in
//! front of the camera lies on the primary ray of view slopes (x / z, y / z)
//! (`Camera::film_at_slopes`):
//! - **a quad wholly in front** (every corner at z > 0) lies in the bounding box of its
//!   corners' slopes (a perspective projection maps convex sets in front of the camera to convex
//!   sets);
//! - **a sphere wholly in front** (centre at z > r) lies between the slopes of its tangents
//!   through the origin, axis by axis. The ball's shadow on the x-z plane is a disk of radius r,
//!   so x / z ranges over (x_c z_c -+ r sqrt(x_c^2 + z_c^2 - r^2)) / (z_c^2 - r^2);
//! - **anything else** (crossing the camera's plane, behind it, or with non-finite terms)
//!   overlaps every tile.
//!
//! The bounds are widened by [`MARGIN`] of the film (and spheres by [`RADIUS_MARGIN`] of their
//! radius). That is orders of magnitude more than the rounding of the primary ray's direction
//! and of the ray tests, about 1e-7 of the view angle: a ray that the tests report as a hit lies
//! inside the widened bounds.
//!
//! [`Scene::intersect_camera`]: crate::scene::Scene::intersect_camera

use crate::geometry::Shape;
use crate::geometry::{Camera, Film};
use crate::num::{Vec3, max0, sqrt};
use crate::words::Words;

/// Tiles across the film.
pub const COLUMNS: u32 = 8;
/// Tiles down the film.
pub const ROWS: u32 = 8;
/// Number of tiles.
const TILES: usize = (COLUMNS * ROWS) as usize;
/// Objects with an index below this get culled (one bit each); the others are always tested.
pub const CULLED: usize = u32::BITS as usize;
/// Object `index`'s bit in a candidate mask; `None` from [`CULLED`] on (always a candidate).
#[inline]
pub(crate) fn object_bit(index: usize) -> Option<u32> {
    u32::try_from(index).ok().and_then(|i| 1u32.checked_shl(i))
}

/// Widening of every image bound, in film units (the film is 1 wide and 1 high).
pub const MARGIN: f32 = 1e-3;
/// Widening of a sphere's radius, relative.
pub const RADIUS_MARGIN: f32 = 1e-3;

/// Where an object can appear on the film.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Image {
    /// Nowhere: no camera ray through the film hits it.
    Off,
    /// Within the pixels from `x.0` to `x.1` and `y.0` to `y.1` (inclusive).
    Pixels { x: (u32, u32), y: (u32, u32) },
    /// Anywhere.
    Everywhere,
}

/// The objects that camera rays through each film tile may hit.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CameraCull {
    /// Bit i of entry `row * COLUMNS + column`: object i may be hit by a camera ray through
    /// that tile.
    masks: [u32; TILES],
    /// A pixel's tile: column `(x * scale.0) >> 16`, row `(y * scale.1) >> 16`.
    scale: (u32, u32),
    film: Film,
}

impl CameraCull {
    /// No objects yet, on `film`.
    pub fn new(film: Film) -> Self {
        // At most 16384 pixels a side: the scale is at least 32, and below 2^16 * tiles / side,
        // so that pixel side - 1 maps to a tile below `tiles`.
        let scale = |side: u32, tiles: u32| (tiles << 16) / side.max(1);
        Self { masks: [0; TILES], scale: (scale(film.width(), COLUMNS), scale(film.height(), ROWS)), film }
    }

    /// The tile column of pixel column `x` (below [`COLUMNS`] for `x` on the film).
    #[inline]
    fn column(&self, x: u32) -> u32 {
        x.wrapping_mul(self.scale.0) >> 16
    }

    /// The tile row of pixel row `y` (below [`ROWS`] for `y` on the film).
    #[inline]
    fn row(&self, y: u32) -> u32 {
        y.wrapping_mul(self.scale.1) >> 16
    }

    /// Adds object `index`, of `shape`, as `camera` (on this film) sees it. (Out of line: it
    /// runs once per object, when the scene is built.)
    #[inline(never)]
    pub fn add(&mut self, index: usize, camera: &Camera, shape: &Shape) {
        let Some(bit) = object_bit(index) else {
            return; // from CULLED on: always tested
        };
        let (columns, rows) = match image(camera, self.film, shape) {
            Image::Off => return,
            Image::Pixels { x, y } => ((self.column(x.0), self.column(x.1)), (self.row(y.0), self.row(y.1))),
            Image::Everywhere => ((0, COLUMNS - 1), (0, ROWS - 1)),
        };
        for row in rows.0..=rows.1 {
            for column in columns.0..=columns.1 {
                if let Some(mask) = self.masks.get_mut((row * COLUMNS + column) as usize) {
                    *mask |= bit;
                }
            }
        }
    }

    /// The objects a camera ray through pixel `(x, y)` may hit: bit i for object i below
    /// [`CULLED`] (the objects from there on may always be hit). Every object for a pixel off
    /// the film.
    #[inline]
    pub fn candidates(&self, x: u32, y: u32) -> u32 {
        if x >= self.film.width() || y >= self.film.height() {
            return u32::MAX;
        }
        let tile = self.row(y) * COLUMNS + self.column(x);
        self.masks.get(tile as usize).copied().unwrap_or(u32::MAX)
    }
}

/// The pixels of `film` whose camera rays may hit `shape` (see the module docs).
fn image(camera: &Camera, film: Film, shape: &Shape) -> Image {
    let Some((a, b)) = slopes(camera, shape) else { return Image::Everywhere };
    // u grows with a, v falls as b grows.
    let (lo, hi) = (camera.film_at_slopes(a.0, b.1), camera.film_at_slopes(a.1, b.0));
    let (u, v) = ((lo.x - MARGIN, hi.x + MARGIN), (lo.y - MARGIN, hi.y + MARGIN));
    // Not finite, or reversed: no bound worth trusting.
    if !(u.0 <= u.1 && v.0 <= v.1) {
        return Image::Everywhere;
    }
    // Pixel x holds the rays of u in [x / width, (x + 1) / width].
    if u.1 < 0.0 || u.0 > 1.0 || v.1 < 0.0 || v.0 > 1.0 {
        return Image::Off;
    }
    Image::Pixels { x: pixels(u, film.width()), y: pixels(v, film.height()) }
}

/// The pixels from the one before that of `range.0` to that of `range.1` along a side of
/// `side` pixels, clamped to the film (`range` is ordered and meets [0, 1]).
fn pixels(range: (f32, f32), side: u32) -> (u32, u32) {
    let last = side.saturating_sub(1);
    let side = side as f32;
    // Clamped before the conversions (which truncate: one pixel early at worst, never late).
    let at = |u: f32| (u.clamp(0.0, 1.0) * side) as u32;
    (at(range.0).saturating_sub(1).min(last), at(range.1).min(last))
}

/// The ranges of the view slopes x / z and y / z of `shape`'s points, seen by `camera`; `None`
/// where they are unbounded (the shape is not wholly in front of the camera).
fn slopes(camera: &Camera, shape: &Shape) -> Option<((f32, f32), (f32, f32))> {
    if let Some((center, radius)) = shape.as_sphere() {
        let c = camera.view_of(center);
        let r = radius * (1.0 + RADIUS_MARGIN);
        let zz = c.z * c.z - r * r;
        if !(c.z > r && zz > 0.0) {
            return None;
        }
        let range = |w: f32| {
            let s = r * sqrt(max0(w * w + zz));
            ((w * c.z - s) / zz, (w * c.z + s) / zz)
        };
        return Some((range(c.x), range(c.y)));
    }
    let corners = shape.corners()?;
    let mut ranges = ((f32::INFINITY, f32::NEG_INFINITY), (f32::INFINITY, f32::NEG_INFINITY));
    corners.iter().all(|&p| widen(camera, p, &mut ranges)).then_some(ranges)
}

/// Widens `ranges` to the view slopes (x / z, y / z) of point `p`, seen by `camera`; false
/// (leaving them) unless the point is in front. (Out of line: a copy for each of a quad's
/// corners would cost flash on a Cortex-M.)
#[inline(never)]
fn widen(camera: &Camera, p: Vec3, ranges: &mut ((f32, f32), (f32, f32))) -> bool {
    let v: Vec3 = camera.view_of(p);
    if !(v.z > 0.0) {
        return false;
    }
    let (x, y) = (v.x / v.z, v.y / v.z);
    let (a, b) = ranges;
    *a = (a.0.min(x), a.1.max(x));
    *b = (b.0.min(y), b.1.max(y));
    true
}

impl CameraCull {
    /// No film and no objects, for a scene that is about to be loaded.
    pub(crate) const EMPTY: CameraCull = CameraCull { masks: [0; TILES], scale: (0, 0), film: Film::ONE };
}

impl crate::words::Image for CameraCull {
    fn put(&self, out: &mut dyn FnMut(u32)) {
        self.masks.iter().for_each(|&m| out(m));
        out(self.scale.0);
        out(self.scale.1);
        self.film.put(out);
    }
    fn get(w: &mut Words<'_>) -> Option<Self> {
        let masks = w.take::<TILES>()?;
        let [sx, sy] = w.take()?;
        Some(CameraCull { masks, scale: (sx, sy), film: Film::get(w)? })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{CameraDesc, FovAxis};
    use crate::num::Vec2;
    use crate::sampling::sampler::Sampler;

    fn camera(film: Film) -> Camera {
        let desc = CameraDesc {
            origin: Vec3::new(0.3, 1.0, 6.0),
            target: Vec3::new(0.0, -0.5, 0.0),
            up: Vec3::Y,
            fov_deg: 50.0,
            fov_axis: FovAxis::Y,
            near_clip: 0.0,
        };
        Camera::new(desc, film).unwrap()
    }

    /// Spheres from tiny to huge and quads of every size and tilt, around, beside, behind and
    /// across the camera's plane, some seen edge on.
    fn shapes(rng: &mut Sampler, n: usize) -> std::vec::Vec<Shape> {
        let mut p = |s: f32| {
            Vec3::new(rng.next_f32() * 2.0 - 1.0, rng.next_f32() * 2.0 - 1.0, rng.next_f32() * 2.0 - 1.0) * s
        };
        let mut v = std::vec::Vec::new();
        for i in 0..n {
            let at = p(5.0) + Vec3::new(0.0, 0.0, 1.0);
            let shape = match i % 4 {
                0 => Shape::sphere(at, 10f32.powf(p(2.5).x - 1.0)),
                1 => {
                    let (e1, e2) = (p(3.0), p(3.0));
                    Shape::quad([at, at + e1, at + e1 + e2, at + e2])
                }
                // Edge on: both edges in a plane through the camera's origin.
                2 => {
                    let o = Vec3::new(0.3, 1.0, 6.0);
                    let (e1, e2) = ((at - o) * 0.3, p(1.0).cross(at - o).normalize() * 2.0);
                    Shape::quad([at, at + e1, at + e1 + e2, at + e2])
                }
                _ => Shape::sphere(at, 1e-3),
            };
            if let Ok(s) = shape {
                v.push(s);
            }
        }
        v
    }

    #[test]
    fn every_hit_is_a_candidate_and_most_objects_are_culled() {
        let mut rng = Sampler::new(9, 2, 7);
        let (mut hits, mut tested, mut culled) = (0u32, 0u32, 0u32);
        for (k, (w, h)) in [(64u32, 48u32), (7, 5), (384, 256), (1, 1), (33, 200)].into_iter().enumerate() {
            let film = Film::new(w, h).unwrap();
            let cam = camera(film);
            let shapes = shapes(&mut rng, 40 + 3 * k);
            let mut cull = CameraCull::new(film);
            for (i, s) in shapes.iter().enumerate() {
                cull.add(i, &cam, s);
            }
            for _ in 0..4000 {
                let (x, y) = (rng.next_u32() % w, rng.next_u32() % h);
                // The pixel's corners, its interior and the film's edges.
                let j = match rng.next_u32() % 4 {
                    0 => Vec2::ZERO,
                    1 => Vec2::new(1.0, 1.0),
                    _ => rng.next_2d(),
                };
                let (ray, t_near) =
                    cam.ray(Vec2::new((x as f32 + j.x) / w as f32, (y as f32 + j.y) / h as f32));
                let candidates = cull.candidates(x, y);
                for (i, s) in shapes.iter().enumerate() {
                    let candidate = i >= CULLED || candidates >> i & 1 == 1;
                    if s.intersect(&ray, t_near, f32::INFINITY).is_some() {
                        assert!(candidate, "object {i} {s:?} hit at pixel ({x}, {y}) of {w}x{h}, {j}");
                        hits += 1;
                    }
                    tested += u32::from(candidate);
                    culled += u32::from(!candidate);
                }
            }
        }
        // Not vacuous: many hits, and more objects culled than tested.
        assert!(hits > 10_000, "{hits}");
        assert!(culled > tested, "{culled} culled, {tested} tested");
    }

    #[test]
    fn objects_behind_or_across_the_camera_are_everywhere_and_off_film_ones_nowhere() {
        let film = Film::new(64, 48).unwrap();
        let cam = camera(film);
        let mut cull = CameraCull::new(film);
        // Behind the camera, around it, and far off to the side.
        let behind = Shape::sphere(Vec3::new(0.3, 1.0, 9.0), 0.5).unwrap();
        let around = Shape::sphere(Vec3::new(0.3, 1.0, 6.0), 0.5).unwrap();
        let aside = Shape::sphere(Vec3::new(40.0, 1.0, 0.0), 0.5).unwrap();
        let across = Shape::quad([
            Vec3::new(-5.0, -1.0, 0.0),
            Vec3::new(5.0, -1.0, 0.0),
            Vec3::new(5.0, -1.0, 9.0),
            Vec3::new(-5.0, -1.0, 9.0),
        ])
        .unwrap();
        for (i, s) in [behind, around, aside, across].iter().enumerate() {
            cull.add(i, &cam, s);
        }
        for (x, y) in [(0, 0), (63, 47), (31, 20), (5, 40)] {
            assert_eq!(cull.candidates(x, y) & 0b1111, 0b1011, "({x}, {y})");
        }
        // Off the film: every object.
        assert_eq!(cull.candidates(64, 0), u32::MAX);
        assert_eq!(cull.candidates(0, 48), u32::MAX);
    }
}
