//! Fixed-point prototype, run by the `fixed-proto` feature (with `measure`): the scene's ray-shape
//! intersection (every object, nearest hit: the kernel's `Shape::intersect` loop) in Q16.16
//! integers against the f32 path, on the camera rays of the film. It prints instructions per
//! ray-object test for both and how often the nearest object and distance agree. Only a
//! measurement: the kernel does not use it.

use core::hint::black_box;

use picomis::{Ray, Shape};
use picomis::{Vec2, Vec3};

use crate::board::scene::SceneT;
use crate::clock;

/// Q16.16: 16 integer bits (with sign), 16 fraction bits.
type Q = i32;
type Q3 = [Q; 3];

const FRAC: u32 = 16;

fn q(x: f32) -> Q {
    // Saturating float-to-int conversion; the prototype's scene fits (|x| < 32768).
    (x * (1 << FRAC) as f32) as i32
}

fn q3(v: Vec3) -> Q3 {
    [q(v.x), q(v.y), q(v.z)]
}

fn to_f32(x: Q) -> f32 {
    x as f32 / (1 << FRAC) as f32
}

/// `a * b` in Q16.16 (floor), from four 16x16-bit products: the M0's MULS keeps only the low
/// 32 bits of a product.
#[inline(always)]
fn qmul(a: Q, b: Q) -> Q {
    let (ah, al) = (a >> 16, (a as u32) & 0xffff);
    let (bh, bl) = (b >> 16, (b as u32) & 0xffff);
    ((ah * bh) << 16)
        .wrapping_add(ah * bl as i32)
        .wrapping_add(al as i32 * bh)
        .wrapping_add(((al * bl) >> 16) as i32)
}

#[inline(always)]
fn dot(a: Q3, b: Q3) -> Q {
    qmul(a[0], b[0]) + qmul(a[1], b[1]) + qmul(a[2], b[2])
}

#[inline(always)]
fn sub(a: Q3, b: Q3) -> Q3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
fn scale(a: Q3, s: Q) -> Q3 {
    [qmul(a[0], s), qmul(a[1], s), qmul(a[2], s)]
}

/// sqrt(x) in Q16.16 for x >= 0: the integer square root of x * 2^16, two bits per step.
#[inline(never)]
fn qsqrt(x: Q) -> Q {
    let x = x.max(0) as u32;
    let (mut root, mut rem) = (0u32, 0u32);
    // x << 16 is 48 bits: 24 steps of two bits, the last 8 from the zero fraction bits.
    let mut bits = x;
    for i in 0..24 {
        let two = if i < 16 {
            let t = bits >> 30;
            bits <<= 2;
            t
        } else {
            0
        };
        rem = (rem << 2) | two;
        let trial = (root << 2) | 1;
        root <<= 1;
        if rem >= trial {
            rem -= trial;
            root |= 1;
        }
    }
    root as i32
}

/// a / b in Q16.16 (b != 0): the dividend shifted up as far as it fits, the divisor down by the
/// rest, one 32-bit division.
#[inline(never)]
fn qdiv(a: Q, b: Q) -> Q {
    let neg = (a < 0) != (b < 0);
    let (ua, ub) = (a.unsigned_abs(), b.unsigned_abs());
    let up = (ua.leading_zeros().max(1) - 1).min(FRAC);
    let den = (ub >> (FRAC - up)).max(1);
    let r = ((ua << up) / den).min(i32::MAX as u32) as i32;
    if neg { -r } else { r }
}

/// A shape in Q16.16.
#[derive(Clone, Copy)]
enum QShape {
    Sphere { center: Q3, r2: Q },
    Quad { p0: Q3, n: Q3, plane: Q, s_axis: Q3, t_axis: Q3 },
    None,
}

fn cross(a: Vec3, b: Vec3) -> Vec3 {
    a.cross(b)
}

impl QShape {
    fn new(shape: &Shape) -> Self {
        if let Some((c, r)) = shape.as_sphere() {
            return QShape::Sphere { center: q3(c), r2: q(r * r) };
        }
        // The quad's corner and edges from its area parametrisation p0 + u.x e1 + u.y e2.
        let p0 = shape.sample_area(Vec2::new(0.0, 0.0)).p;
        let e1 = shape.sample_area(Vec2::new(1.0, 0.0)).p - p0;
        let e2 = shape.sample_area(Vec2::new(0.0, 1.0)).p - p0;
        let c = cross(e1, e2);
        let len2 = c.dot(c);
        if len2 <= 0.0 {
            return QShape::None;
        }
        let w = c / len2;
        let n = shape.normal_at(p0);
        QShape::Quad {
            p0: q3(p0),
            n: q3(n),
            plane: q(n.dot(p0)),
            s_axis: q3(cross(e2, w)),
            t_axis: q3(cross(w, e1)),
        }
    }

    /// Distance to the nearest hit in (t_min, t_max): the same steps as `Shape::intersect`.
    #[inline(never)]
    fn intersect(&self, o: Q3, d: Q3, t_min: Q, t_max: Q) -> Option<Q> {
        match *self {
            QShape::Sphere { center, r2 } => {
                let f = sub(o, center);
                let b = dot(f, d);
                let l = sub(f, scale(d, b));
                let disc = r2 - dot(l, l);
                if disc < 0 {
                    return None;
                }
                let c = dot(f, f) - r2;
                let s = qsqrt(disc);
                let qq = if b >= 0 { -b - s } else { -b + s };
                let (t0, t1) = if qq != 0 { (qdiv(c, qq), qq) } else { (0, 0) };
                let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
                if near > t_min && near < t_max {
                    Some(near)
                } else if far > t_min && far < t_max {
                    Some(far)
                } else {
                    None
                }
            }
            QShape::Quad { p0, n, plane, s_axis, t_axis } => {
                let denom = dot(n, d);
                if denom == 0 {
                    return None;
                }
                let t = qdiv(plane - dot(n, o), denom);
                if !(t > t_min && t < t_max) {
                    return None;
                }
                let p = sub([o[0] + qmul(d[0], t), o[1] + qmul(d[1], t), o[2] + qmul(d[2], t)], p0);
                let (s, v) = (dot(p, s_axis), dot(p, t_axis));
                ((0..=1 << FRAC).contains(&s) && (0..=1 << FRAC).contains(&v)).then_some(t)
            }
            QShape::None => None,
        }
    }
}

/// Objects the prototype takes (the Veach scene has 11).
const MAX_SHAPES: usize = 16;

fn time(f: impl FnOnce()) -> u64 {
    let t0 = clock::ticks();
    f();
    clock::ticks() - t0
}

/// Nearest (object, t) over the scene in f32.
#[inline(never)]
fn nearest_f32(scene: &SceneT, ray: &Ray) -> Option<(usize, f32)> {
    let mut best: Option<(usize, f32)> = None;
    for (i, o) in scene.objects().iter().enumerate() {
        let t_max = best.map_or(f32::INFINITY, |b| b.1);
        if let Some(t) = o.shape.intersect(ray, 0.0, t_max) {
            best = Some((i, t));
        }
    }
    best
}

/// Nearest (object, t) over the scene in Q16.16.
#[inline(never)]
fn nearest_q(shapes: &[QShape], o: Q3, d: Q3) -> Option<(usize, Q)> {
    let mut best: Option<(usize, Q)> = None;
    for (i, s) in shapes.iter().enumerate() {
        let t_max = best.map_or(i32::MAX, |b| b.1);
        if let Some(t) = s.intersect(o, d, 0, t_max) {
            best = Some((i, t));
        }
    }
    best
}

/// Runs the comparison on the film's pixel-center camera rays; `cal` converts ticks to
/// instructions (instructions, ticks).
#[inline(never)]
pub fn run(scene: &SceneT, cal: (u64, u64)) {
    let mut shapes = [QShape::None; MAX_SHAPES];
    let n = scene.objects().len().min(MAX_SHAPES);
    for (s, o) in shapes.iter_mut().zip(scene.objects()) {
        *s = QShape::new(&o.shape);
    }
    let shapes = &shapes[..n];
    let film = scene.film();
    let (w, h) = (film.width(), film.height());
    let ray_at = |x: u32, y: u32| {
        let uv = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
        scene.camera().ray(uv).0
    };
    // Rays are made outside the timed loops (in f32 for both).
    let instr = |t: u64| (t * cal.0 + cal.1 / 2) / cal.1;
    let (mut tf, mut tq) = (0u64, 0u64);
    let (mut same, mut hits, mut close) = (0u32, 0u32, 0u32);
    for y in 0..h {
        for x in 0..w {
            let ray = ray_at(x, y);
            let (o, d) = (q3(ray.origin), q3(ray.dir));
            let mut rf = None;
            let mut rq = None;
            tf += time(|| rf = black_box(nearest_f32(scene, black_box(&ray))));
            tq += time(|| rq = black_box(nearest_q(shapes, black_box(o), black_box(d))));
            let empty = time(|| black_box(()));
            tf = tf.saturating_sub(empty);
            tq = tq.saturating_sub(empty);
            match (rf, rq) {
                (Some((i, t)), Some((j, u))) if i == j => {
                    same += 1;
                    hits += 1;
                    let err = to_f32(u) - t;
                    if err.abs() <= 1e-3 * t.max(1.0) {
                        close += 1;
                    }
                }
                (None, None) => same += 1,
                (Some(_), _) => hits += 1,
                _ => {}
            }
        }
    }
    let tests = u64::from(w * h) * n as u64;
    let (f, qi) = (instr(tf), instr(tq));
    info!("fixed point: {} camera rays x {} objects, nearest hit (Q16.16 prototype)", w * h, n as u32);
    info!(
        "fixed point: per ray-object test: f32 {} instructions, Q16.16 {}",
        (f / tests) as u32,
        (qi / tests) as u32
    );
    info!(
        "fixed point: same nearest object on {} of {} rays; t within 0.1 % on {} of {} hits",
        same,
        w * h,
        close,
        hits
    );
}
