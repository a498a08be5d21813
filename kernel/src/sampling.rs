//! Every sampling routine with its pdf, as `sample_x` / `x_pdf` pairs. Random numbers come in as
//! `u`; directions are in a local frame whose `z` axis is the normal (or the cone axis).
//! Pdfs are per unit solid angle for directions and per unit area for points.

use crate::math::{
    INV_PI, PI, Vec2, Vec3, atan2, clamp, dot, finite3, magnitude_bits, max0, normalize_or, positive_finite,
    safe_sqrt, sin_cos_eighths, sin_cos_turns, sqrt, try_normalize,
};

/// Concentric map of the unit square to the unit disk (Shirley and Chiu 1997).
#[inline]
pub fn sample_concentric_disk(u: Vec2) -> Vec2 {
    let o = u * 2.0 - Vec2::ONE;
    // The comparisons of magnitudes on the bits (the same answers for values that are not NaN;
    // on a soft-float core no comparison routine).
    let (mx, my) = (magnitude_bits(o.x), magnitude_bits(o.y));
    if mx == 0 && my == 0 {
        return Vec2::ZERO;
    }
    // theta = pi/4 (y/x) in the left and right wedges, pi/2 - pi/4 (x/y) in the others:
    // only sines and cosines of |angle| <= pi/4 are needed.
    let (r, s, c) = if mx > my {
        let (s, c) = sin_cos_eighths(o.y / o.x);
        (o.x, s, c)
    } else {
        let (s, c) = sin_cos_eighths(o.x / o.y);
        (o.y, c, s)
    };
    Vec2::new(c, s) * r
}

/// Cosine-weighted direction on the upper hemisphere (Malley's method).
#[inline]
pub fn sample_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = sample_concentric_disk(u);
    Vec3::new(d.x, d.y, safe_sqrt(1.0 - d.x * d.x - d.y * d.y))
}

/// Pdf of [`sample_cosine_hemisphere`]: cos(theta) / pi on the upper hemisphere, else 0.
#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    if cos_theta > 0.0 { cos_theta * INV_PI } else { 0.0 }
}

/// Uniform direction on the unit sphere (also: a uniform point on a sphere of any radius).
#[inline]
pub fn sample_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = safe_sqrt(1.0 - z * z);
    let (s, c) = sin_cos_turns(u.y);
    Vec3::new(r * c, r * s, z)
}

/// Pdf of [`sample_uniform_sphere`] per unit solid angle: 1 / (4 pi).
#[inline]
pub fn uniform_sphere_pdf() -> f32 {
    0.25 * INV_PI
}

/// `1 - cos(theta_max)` of the cone that a sphere subtends, from `sin^2(theta_max) = r^2 / d^2`,
/// computed as `sin^2 / (1 + cos)`: exact to f32 precision down to r/d = 1e-6, where the naive
/// `1 - sqrt(1 - sin^2)` rounds to zero. Sampling and pdf both call this one routine.
#[inline]
pub fn cone_one_minus_cos(sin2_theta_max: f32) -> f32 {
    let sin2 = if sin2_theta_max < 1.0 { max0(sin2_theta_max) } else { 1.0 };
    sin2 / (1.0 + safe_sqrt(1.0 - sin2))
}

/// Uniform direction inside the cone around local `z` with the given `1 - cos(theta_max)`,
/// through the concentric disk (the low-distortion map Mitsuba 3 uses too): a uniform point `p`
/// on the unit disk has `|p|^2` uniform in [0, 1], so `1 - cos(theta) = |p|^2 (1 - cos(theta_max))`
/// and the azimuth is `p`'s. Neighbouring `u` stay neighbouring directions, so a stratified `u`
/// stays stratified on the cone (the polar map squeezes one row of strata into the axis).
#[inline]
pub fn sample_uniform_cone(u: Vec2, one_minus_cos_max: f32) -> Vec3 {
    let p = sample_concentric_disk(u);
    // 1 - cos(theta), kept in that form for precision.
    let one_minus_cos = (p.x * p.x + p.y * p.y) * one_minus_cos_max;
    // sin(theta) / |p| = sqrt((1 - cos_max) (2 - (1 - cos))).
    let k = safe_sqrt(one_minus_cos_max * (2.0 - one_minus_cos));
    Vec3::new(p.x * k, p.y * k, 1.0 - one_minus_cos)
}

/// Pdf of [`sample_uniform_cone`] per unit solid angle: 1 / (2 pi (1 - cos theta_max)).
#[inline]
pub fn uniform_cone_pdf(one_minus_cos_max: f32) -> f32 {
    if one_minus_cos_max > 0.0 { 1.0 / (2.0 * PI * one_minus_cos_max) } else { 0.0 }
}

/// Uniform point on the parallelogram `p0 + s e1 + t e2`, as its (s, t) coordinates.
#[inline]
pub fn sample_parallelogram(u: Vec2) -> Vec2 {
    u
}

/// Pdf of [`sample_parallelogram`] per unit area: 1 / area.
#[inline]
pub fn parallelogram_pdf(area: f32) -> f32 {
    if area > 0.0 { 1.0 / area } else { 0.0 }
}

/// A rectangle seen from a point, set up for uniform sampling in solid angle (Ureña, Fajardo and
/// King 2013, "An Area-Preserving Parametrization for Spherical Rectangles"). Local frame: the
/// point at the origin, the rectangle's edges along `x` and `y`, its front normal along `z`; it
/// spans [x0, x1] x [y0, y1] in the plane z = z0 < 0 (the point sees its front side).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphericalRectangle {
    x0: f32,
    x1: f32,
    y0: f32,
    y1: f32,
    z0: f32,
    /// z components of the normals of the planes through the point and the edges y = y0, y = y1.
    b0: f32,
    b1: f32,
    /// g2 + g3 - pi: the angles at the corners (x0, y1) and (x0, y0), minus their flat value.
    k: f32,
    /// The solid angle.
    solid_angle: f32,
}

/// The relative size below which a spherical rectangle's solid angle is not trusted (see
/// [`spherical_rectangle`]).
pub const SPHERICAL_RECTANGLE_MIN_RELATIVE: f32 = 1e-3;
/// The smallest solid angle sampled as a spherical rectangle.
pub const SPHERICAL_RECTANGLE_MIN_SOLID_ANGLE: f32 = 1e-6;

/// Sets up [`sample_spherical_rectangle`] for the rectangle whose corner (x0, y0, z0) is `corner`
/// in the local frame, with edge lengths `ex` and `ey`. `None` when the point is not in front of
/// the rectangle (z0 >= 0) or when f32 cannot resolve its solid angle: the caller then samples by
/// area. The solid angle is the sum of the corners' angles minus 2 pi, computed as the sum of
/// delta_i = g_i - pi/2 = atan2(s x y, |z0| |v|) at each corner v = (x, y, z0) (s = +1 at (x1, y1)
/// and (x0, y0), -1 at the others): no acos and no cancellation against 2 pi. It is trusted when
/// it is at least 1e-6 sr and at least 1e-3 of sum |delta_i| (cancellation between the corners'
/// terms, for rectangles seen far off their axis). The test is on f32 values computed the same
/// way everywhere, so the host and a Cortex-M make the same choice.
#[inline]
pub fn spherical_rectangle(corner: Vec3, ex: f32, ey: f32) -> Option<SphericalRectangle> {
    let (x0, y0, z0) = (corner.x, corner.y, corner.z);
    if !(z0 < 0.0) || !(ex > 0.0) || !(ey > 0.0) || !finite3(corner) || !(ex + ey).is_finite() {
        return None;
    }
    let (x1, y1) = (x0 + ex, y0 + ey);
    let h = -z0;
    let (z2, x02, x12, y02, y12) = (z0 * z0, x0 * x0, x1 * x1, y0 * y0, y1 * y1);
    let corner_angle = |xy: f32, r2: f32| atan2(xy, h * sqrt(r2));
    let d0 = corner_angle(-(x1 * y0), x12 + y02 + z2);
    let d1 = corner_angle(x1 * y1, x12 + y12 + z2);
    let d2 = corner_angle(-(x0 * y1), x02 + y12 + z2);
    let d3 = corner_angle(x0 * y0, x02 + y02 + z2);
    let solid_angle = (d0 + d1) + (d2 + d3);
    let scale = (d0.abs() + d1.abs()) + (d2.abs() + d3.abs());
    let trusted = solid_angle >= SPHERICAL_RECTANGLE_MIN_SOLID_ANGLE
        && solid_angle >= SPHERICAL_RECTANGLE_MIN_RELATIVE * scale
        && solid_angle.is_finite();
    trusted.then(|| SphericalRectangle {
        x0,
        x1,
        y0,
        y1,
        z0,
        b0: -y0 / sqrt(z2 + y02),
        b1: y1 / sqrt(z2 + y12),
        k: d2 + d3,
        solid_angle,
    })
}

/// A point (local frame, relative to the viewing point) on the rectangle, uniformly distributed
/// in solid angle (Ureña et al. 2013; the steps of pbrt-v4's `SampleSphericalRectangle`, with the
/// first angle kept relative to pi for precision). `None` only for non-finite rounding outcomes.
#[inline]
pub fn sample_spherical_rectangle(r: &SphericalRectangle, u: Vec2) -> Option<Vec3> {
    // The angle a_u = u S + 2 pi - g2 - g3 of the paper is pi + phi.
    let phi = u.x * r.solid_angle - r.k;
    let (sin_phi, cos_phi) = sin_cos_turns(phi * (0.5 * INV_PI));
    let fu = (cos_phi * r.b0 + r.b1) / sin_phi;
    let cu = 1.0 / sqrt(fu * fu + r.b0 * r.b0);
    let cu = if fu < 0.0 { -cu } else { cu };
    let cu = clamp(cu, -0.999_999_94, 0.999_999_94);
    let xu = clamp(-(cu * r.z0) / safe_sqrt(1.0 - cu * cu), r.x0, r.x1);
    let d2 = xu * xu + r.z0 * r.z0;
    let d = sqrt(d2);
    let h0 = r.y0 / sqrt(d2 + r.y0 * r.y0);
    let h1 = r.y1 / sqrt(d2 + r.y1 * r.y1);
    let hv = h0 + u.y * (h1 - h0);
    let hv2 = hv * hv;
    let yv = if hv2 < 1.0 - 1e-6 { clamp(hv * d / sqrt(1.0 - hv2), r.y0, r.y1) } else { r.y1 };
    let p = Vec3::new(xu, yv, r.z0);
    (xu.is_finite() && yv.is_finite()).then_some(p)
}

/// Pdf of [`sample_spherical_rectangle`] per unit solid angle: 1 / solid angle.
#[inline]
pub fn spherical_rectangle_pdf(r: &SphericalRectangle) -> f32 {
    1.0 / r.solid_angle
}

impl SphericalRectangle {
    /// The solid angle the rectangle subtends.
    pub fn solid_angle(&self) -> f32 {
        self.solid_angle
    }
}

/// The random numbers with which [`sample_spherical_rectangle`] reaches the point `p` of the
/// rectangle (local frame; only its x and y are read, clamped to the rectangle): the inverse of
/// the map, in closed form. u.x is the solid angle of the part x0 <= x <= p.x over the whole
/// (the sum of that part's corner terms, as in [`spherical_rectangle`]); u.y is where
/// y / sqrt(x^2 + y^2 + z0^2) lies between its values at y0 and y1. Both are in [0, 1].
#[inline]
pub fn invert_spherical_rectangle_sample(r: &SphericalRectangle, p: Vec3) -> Vec2 {
    let xu = clamp(p.x, r.x0, r.x1);
    let yv = clamp(p.y, r.y0, r.y1);
    let d2 = xu * xu + r.z0 * r.z0;
    let corner_angle = |xy: f32, r2: f32| atan2(xy, -r.z0 * sqrt(r2));
    let part = (corner_angle(xu * r.y1, d2 + r.y1 * r.y1) - corner_angle(xu * r.y0, d2 + r.y0 * r.y0)) + r.k;
    let ux = part / r.solid_angle;
    let h = |y: f32| y / sqrt(d2 + y * y);
    let (h0, h1) = (h(r.y0), h(r.y1));
    let uy = if h1 > h0 { (h(yv) - h0) / (h1 - h0) } else { 0.5 };
    let unit = |v: f32| if v > 0.0 { if v < 1.0 { v } else { 1.0 } } else { 0.0 };
    Vec2::new(unit(ux), unit(uy))
}

/// The largest f32 below 1: samples on [0, 1) stay below it.
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// A point of [0, 1) with density proportional to (1 - x) a + x b (`a`, `b` finite and
/// non-negative; uniform when both are 0), by inverting its cdf:
/// x = u (a + b) / (a + sqrt((1 - u) a^2 + u b^2)) (pbrt-v4's `SampleLinear`).
#[inline]
pub fn sample_linear(u: f32, a: f32, b: f32) -> f32 {
    let sum = a + b;
    if !(sum > 0.0) {
        return clamp(u, 0.0, ONE_MINUS_EPSILON);
    }
    let denominator = a + sqrt((1.0 - u) * (a * a) + u * (b * b));
    let x = if denominator > 0.0 { u * sum / denominator } else { 0.0 };
    clamp(x, 0.0, ONE_MINUS_EPSILON)
}

/// Pdf of [`sample_linear`]: 2 ((1 - x) a + x b) / (a + b) on [0, 1] (1 when a + b = 0), else 0.
#[inline]
pub fn linear_pdf(x: f32, a: f32, b: f32) -> f32 {
    let sum = a + b;
    if !(0.0..=1.0).contains(&x) {
        0.0
    } else if !(sum > 0.0) {
        1.0
    } else {
        2.0 * ((1.0 - x) * a + x * b) / sum
    }
}

/// A point of [0, 1)^2 with density proportional to the bilinear interpolation of the corner
/// values `w` at (0, 0), (1, 0), (0, 1) and (1, 1) (finite, non-negative): y from its marginal,
/// then x given y, each by [`sample_linear`] (pbrt-v4's `SampleBilinear`).
#[inline]
pub fn sample_bilinear(u: Vec2, w: [f32; 4]) -> Vec2 {
    let [w00, w10, w01, w11] = w;
    let y = sample_linear(u.y, w00 + w10, w01 + w11);
    let x = sample_linear(u.x, (1.0 - y) * w00 + y * w01, (1.0 - y) * w10 + y * w11);
    Vec2::new(x, y)
}

/// Pdf of [`sample_bilinear`] on the unit square: 4 bilerp(w; p) / (w00 + w10 + w01 + w11)
/// (1 when every weight is 0), 0 outside it.
#[inline]
pub fn bilinear_pdf(p: Vec2, w: [f32; 4]) -> f32 {
    let [w00, w10, w01, w11] = w;
    let (x, y) = (p.x, p.y);
    let sum = (w00 + w10) + (w01 + w11);
    if !((0.0..=1.0).contains(&x) && (0.0..=1.0).contains(&y)) {
        0.0
    } else if !(sum > 0.0) {
        1.0
    } else {
        let bilerp = (1.0 - y) * ((1.0 - x) * w00 + x * w10) + y * ((1.0 - x) * w01 + x * w11);
        4.0 * bilerp / sum
    }
}

/// The smallest corner weight of the cosine warp (pbrt-v4's 0.01): corners below the receiver's
/// horizon keep some density, so every direction to the rectangle keeps a positive pdf.
pub const COSINE_WARP_FLOOR: f32 = 0.01;

/// The corner weights of the cosine-warped spherical rectangle (Hart, Pharr, Müller, Lopes,
/// McGuire and Shirley 2020, "Practical Product Sampling by Fitting and Composing Warps"): the
/// receiver's cosines max([`COSINE_WARP_FLOOR`], n . v / |v|) towards the corners (x0, y0),
/// (x1, y0), (x0, y1), (x1, y1), which [`sample_spherical_rectangle`] reaches at u = (0, 0),
/// (1, 0), (0, 1), (1, 1). `n` is the receiver's unit normal in the rectangle's local frame.
/// Warping u by [`sample_bilinear`] with them draws directions roughly in proportion to the
/// cosine; the pdf is [`spherical_rectangle_pdf`] times [`bilinear_pdf`] at the u of the
/// direction ([`invert_spherical_rectangle_sample`]).
#[inline]
pub fn spherical_rectangle_cosines(r: &SphericalRectangle, n: Vec3) -> [f32; 4] {
    let cosine = |x: f32, y: f32| {
        let v = Vec3::new(x, y, r.z0);
        let c = n.dot(v) / sqrt(v.length_squared());
        if c > COSINE_WARP_FLOOR { c } else { COSINE_WARP_FLOOR }
    };
    [cosine(r.x0, r.y0), cosine(r.x1, r.y0), cosine(r.x0, r.y1), cosine(r.x1, r.y1)]
}

/// An isotropic GGX roughness with the powers of alpha that [`GgxAlpha::d`] and
/// [`GgxAlpha::g1`] use, computed once (a shading point evaluates D and G1 several times).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GgxAlpha {
    /// alpha.
    pub alpha: f32,
    /// alpha^2.
    a2: f32,
    /// 1 - alpha^2.
    one_minus_a2: f32,
    /// pi alpha^2.
    pi_a2: f32,
}

impl GgxAlpha {
    /// The roughness `alpha`.
    #[inline]
    pub fn new(alpha: f32) -> Self {
        let a2 = alpha * alpha;
        Self { alpha, a2, one_minus_a2: 1.0 - a2, pi_a2: PI * a2 }
    }

    /// The normal distribution D(m), `m` in the local frame. Written as
    /// 1 / (pi a^2 (m_z^2 + (m_x^2 + m_y^2)/a^2)^2), which neither overflows nor loses precision
    /// for alpha down to 1e-4.
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let t = (m.x * m.x + m.y * m.y) / self.a2 + m.z * m.z;
        1.0 / (self.pi_a2 * t * t)
    }

    /// Smith masking G1(v): 2 / (1 + sqrt(1 + a^2 tan^2 theta_v)), 0 below the horizon; for
    /// the unit `v`, with tan^2 = (1 - cos^2) / cos^2, as 2 cos / (cos + sqrt(a^2 + (1 - a^2)
    /// cos^2)): no cancellation (a sum of positive terms under the root), one division.
    #[inline]
    pub fn g1(&self, v: Vec3) -> f32 {
        if v.z <= 0.0 {
            return 0.0;
        }
        (v.z + v.z) / (v.z + sqrt(self.a2 + self.one_minus_a2 * (v.z * v.z)))
    }
}

/// GGX normal distribution D(m) for isotropic `alpha`, `m` in the local frame ([`GgxAlpha::d`]).
#[inline]
pub fn ggx_d(m: Vec3, alpha: f32) -> f32 {
    GgxAlpha::new(alpha).d(m)
}

/// Smith masking G1(v) for GGX ([`GgxAlpha::g1`]), 0 below the horizon.
#[inline]
pub fn ggx_g1(v: Vec3, alpha: f32) -> f32 {
    GgxAlpha::new(alpha).g1(v)
}

/// Microfacet normal from the GGX distribution of normals visible from `wo`, by spherical caps
/// (Dupuy and Benyoub 2023, "Sampling Visible GGX Normals with Spherical Caps"): in the
/// stretched configuration, where the roughness is one, the visible normals are the directions
/// `c + v` for `c` uniform on the cap of the unit sphere with `z > -v.z` (`v` the stretched
/// `wo`); unstretching gives the sample. The same distribution as Heitz's (2018) construction
/// with a tangent frame, in about half the operations. `wo` must be in the upper hemisphere.
#[inline]
pub fn sample_ggx_vndf(wo: Vec3, alpha: f32, u: Vec2) -> Vec3 {
    // Stretch the view direction to the hemisphere configuration.
    let v = normalize_or(Vec3::new(alpha * wo.x, alpha * wo.y, wo.z), Vec3::Z);
    // A uniform direction c on the spherical cap z in (-v.z, 1]: z uniform, azimuth uniform.
    let z = (1.0 - u.x) * (1.0 + v.z) - v.z;
    let sin_theta = safe_sqrt(1.0 - z * z);
    let (s, c) = sin_cos_turns(u.y);
    let h = Vec3::new(sin_theta * c + v.x, sin_theta * s + v.y, z + v.z);
    // Unstretch.
    normalize_or(Vec3::new(alpha * h.x, alpha * h.y, max0(h.z)), Vec3::Z)
}

/// Pdf of [`sample_ggx_vndf`] per unit solid angle of microfacet normals:
/// D_wo(m) = G1(wo) max(0, wo.m) D(m) / cos(theta_o).
#[inline]
pub fn ggx_vndf_pdf(wo: Vec3, m: Vec3, alpha: f32) -> f32 {
    if wo.z <= 0.0 {
        return 0.0;
    }
    ggx_g1(wo, alpha) * max0(wo.dot(m)) * ggx_d(m, alpha) / wo.z
}

/// Where a unit direction lies against a convex spherical polygon (a polygonal light seen from a
/// point): the edge whose great circle it lies farthest outside of or, inside the polygon,
/// nearest to ([`nearest_edge`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NearestEdge {
    /// The sine of the direction's angle inside the edge's great circle (negative outside): for
    /// a direction outside the polygon, a lower bound of its angle to it.
    pub sine: f32,
    /// The unit normal of the edge's plane, towards the polygon.
    pub normal: Vec3,
}

/// The edge of the convex spherical polygon with corners in the directions `corners` (in order,
/// of any length) nearest the unit direction `d` ([`NearestEdge`]); `None` where two
/// consecutive corners are parallel.
#[inline]
pub fn nearest_edge<const N: usize>(d: Vec3, corners: &[Vec3; N]) -> Option<NearestEdge> {
    let mut nearest = NearestEdge { sine: f32::INFINITY, normal: Vec3::ZERO };
    let mut prev = *corners.last()?;
    for (i, &c) in corners.iter().enumerate() {
        let n = try_normalize(prev.cross(c))?;
        // The corner after this edge's end is on the polygon's side of its plane.
        let next = *corners.get((i + 1) % N)?;
        let normal = if dot(n, next) < 0.0 { -n } else { n };
        let sine = dot(d, normal);
        if sine < nearest.sine {
            nearest = NearestEdge { sine, normal };
        }
        prev = c;
    }
    Some(nearest)
}

/// A box of GGX microfacet slopes, t0 <= s . g <= t1 along the unit `g` and w0 <= s . g' <= w1
/// across it (g' = `g` turned by a quarter), sampled by the isotropic slope distribution
/// P22(s) = 1 / (pi a^2 (1 + |s|^2 / a^2)^2) (Walter et al. 2007; D(m) cos^4(theta_m) = P22)
/// restricted to it: the samples follow the glossy lobe inside the box. P22 is a bivariate
/// Student t with 2 degrees of freedom: its marginal along `g` has the closed-form tail
/// 1 - F(t) = 1/2 - t / (2 sqrt(a^2 + t^2)), and its conditional across, of scale
/// b = sqrt(a^2 + t^2), is (2 b^3 / pi) / (b^2 + w^2)^2, which [`sample_ggx_slope_in`] follows
/// with an algebraic stand-in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlopeBox {
    /// GGX alpha.
    pub alpha: f32,
    /// Unit direction of the first coordinate.
    pub g: Vec2,
    /// The box along `g`.
    pub t: Vec2,
    /// The box across `g`.
    pub w: Vec2,
    /// The marginal's tail beyond t1, 1 - F(t1).
    tail: f32,
    /// The marginal's mass in [t0, t1].
    mass: f32,
}

/// The tail 1 - F(t) of P22's marginal, for t > 0 as a^2 / (2 r (r + t)) (r = sqrt(a^2 + t^2)),
/// free of the cancellation of 1/2 - t / 2r.
#[inline]
fn slope_tail(a2: f32, t: f32) -> f32 {
    let r = sqrt(a2 + t * t);
    if t > 0.0 { a2 / (2.0 * r * (r + t)) } else { 0.5 - t / (2.0 * r) }
}

impl SlopeBox {
    /// The box `t` (t0 <= t1) along the unit `g` and `w` (w0 <= w1) across it, for `alpha`;
    /// `None` where the lobe's mass in the strip along `g` is not a positive f32.
    #[inline]
    pub fn new(alpha: f32, g: Vec2, t: Vec2, w: Vec2) -> Option<Self> {
        let a2 = alpha * alpha;
        let tail = slope_tail(a2, t.y);
        let mass = slope_tail(a2, t.x) - tail;
        (positive_finite(mass) && positive_finite(a2) && t.x <= t.y && w.x < w.y && (w.y - w.x).is_finite())
            .then_some(Self { alpha, g, t, w, tail, mass })
    }

    /// The box of a GGX receiver's slopes (seen from local `wo`) that reflect into the cone of
    /// unit `axis` and half-angle theta_max (local; `cos_max` and `sin_max` its cosine and
    /// sine). Its near side is the tangent, in slope space, to the image of the cone's edge at
    /// the edge's point nearest the mirror direction of `wo` (exact to first order there, where
    /// the lobe meets the edge); its other sides are the bounds of the images of eight points of
    /// the edge. `None` when the mirror direction is on the axis (no nearest edge), a half
    /// vector of the edge is not above the receiver, or the box is not usable.
    #[inline]
    pub fn facing_cone(wo: Vec3, alpha: f32, axis: Vec3, cos_max: f32, sin_max: f32) -> Option<Self> {
        let mirror = Vec3::new(-wo.x, -wo.y, wo.z);
        // The unit tangent at the axis towards the mirror direction, and the one across it.
        let toward = try_normalize(mirror - axis * dot(mirror, axis))?;
        let side = axis.cross(toward);
        let edge = axis * cos_max + toward * sin_max;
        const H: f32 = core::f32::consts::FRAC_1_SQRT_2;
        const RING: [(f32, f32); 7] =
            [(H, H), (0.0, 1.0), (-H, H), (-1.0, 0.0), (-H, -H), (0.0, -1.0), (H, -H)];
        let ring =
            RING.map(|(c, s)| half_vector_slope(wo + axis * cos_max + (toward * c + side * s) * sin_max));
        Self::facing(wo, alpha, edge, side, axis * sin_max - toward * cos_max, ring.into_iter())
    }

    /// The box of a GGX receiver's slopes (seen from local `wo`) that reflect towards a convex
    /// polygonal light, whose edge nearest the mirror direction of `wo` is `edge`
    /// ([`nearest_edge`]). The edge spans a great circle of directions; the box's near side is
    /// the tangent, in slope space, to its image at its point nearest the mirror direction
    /// (exact to first order there, as [`SlopeBox::facing_cone`]); its other sides are the
    /// bounds of the images of that point and of `outline` (unit directions to points of the
    /// light's outline). `None` where a half vector is not above the receiver or the box is not
    /// usable.
    #[inline]
    pub fn facing_edge<const M: usize>(
        wo: Vec3,
        alpha: f32,
        edge: &NearestEdge,
        outline: &[Vec3; M],
    ) -> Option<Self> {
        let mirror = Vec3::new(-wo.x, -wo.y, wo.z);
        // The edge's point nearest the mirror direction, and its tangents along and inward.
        let nearest = try_normalize(mirror - edge.normal * edge.sine)?;
        let others = outline.iter().map(|d| half_vector_slope(wo + *d));
        Self::facing(wo, alpha, nearest, edge.normal.cross(nearest), edge.normal, others)
    }

    /// The box whose near side is the tangent, in slope space, to the image of a light's outline
    /// at the unit direction `at` (local, the outline's point nearest the mirror direction of
    /// `wo`), where the outline runs along the tangent `along` and the light lies towards the
    /// tangent `inward`; its other sides bound the images of `at` and the slopes `others` (of
    /// other points of the outline). `None` where one is `None`, the image of `at` is not above
    /// the receiver, or the box is not usable.
    #[inline]
    fn facing(
        wo: Vec3,
        alpha: f32,
        at: Vec3,
        along: Vec3,
        inward: Vec3,
        others: impl Iterator<Item = Option<Vec2>>,
    ) -> Option<Self> {
        // Slopes of half vectors v = wo + wi (unnormalized): s = -(v_x, v_y) / v_z, and the
        // slope-space image of a direction dwi at `at`: -(dwi_xy v_z - v_xy dwi_z) / v_z^2.
        let v = wo + at;
        let near = half_vector_slope(v)?;
        let image = |d: Vec3| Vec2::new(v.x * d.z - d.x * v.z, v.y * d.z - d.y * v.z);
        let (along, inward) = (image(along), image(inward));
        let normal = Vec2::new(-along.y, along.x);
        let g = if normal.dot(inward) < 0.0 { -normal } else { normal };
        let len = sqrt(g.dot(g));
        if !(len > 0.0 && len.is_finite()) {
            return None;
        }
        let g = g / len;
        let (lo, hi) = slope_bounds(g, core::iter::once(Some(near)).chain(others))?;
        Self::new(alpha, g, Vec2::new(near.dot(g), hi.x), Vec2::new(lo.y, hi.y))
    }

    /// Whether the box holds every slope within `radius` of the mirror direction's (0).
    #[inline]
    pub fn holds_disc(&self, radius: f32) -> bool {
        self.t.x < -radius && self.t.y > radius && self.w.x < -radius && self.w.y > radius
    }
}

/// The bounds of `slopes` along the unit `g` (x) and across it (y); `None` if one is `None`.
#[inline]
fn slope_bounds(g: Vec2, slopes: impl Iterator<Item = Option<Vec2>>) -> Option<(Vec2, Vec2)> {
    let across = Vec2::new(-g.y, g.x);
    let (mut lo, mut hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
    for p in slopes {
        let p = p?;
        let q = Vec2::new(p.dot(g), p.dot(across));
        lo = lo.min(q);
        hi = hi.max(q);
    }
    Some((lo, hi))
}

/// The microfacet slope -(v_x, v_y) / v_z of the half vector along `v` (unnormalized), if `v`
/// points above the surface.
#[inline]
fn half_vector_slope(v: Vec3) -> Option<Vec2> {
    (v.z > 0.0).then(|| Vec2::new(-v.x / v.z, -v.y / v.z))
}

/// A slope from P22 in the box `h` (see [`SlopeBox`]): along `g` by inverting the marginal
/// (t = a (1 - 2y) / (2 sqrt(y (1 - y))) for the tail y = 1 - F(t), drawn in its range), across
/// from the density b^2 / (b^2 + w^2)^(3/2) cut to [w0, w1]: sin(atan(w / b)) = w / sqrt(b^2 +
/// w^2) uniform between its values at the box's sides, so w = b s / sqrt(1 - s^2), algebraic
/// (P22's own conditional, proportional to (b^2 + w^2)^-2, has no closed-form inverse; this
/// stand-in has its peak and width, and a tail heavier by sqrt(b^2 + w^2) / b). `None` where the
/// slope is not finite.
#[inline]
pub fn sample_ggx_slope_in(h: &SlopeBox, u: Vec2) -> Option<Vec2> {
    let y = h.tail + h.mass * (1.0 - u.x);
    let t = h.alpha * (1.0 - 2.0 * y) / (2.0 * sqrt(y * (1.0 - y)));
    let b2 = h.alpha * h.alpha + t * t;
    let (s0, s1) = (sine_across(h.w.x, b2), sine_across(h.w.y, b2));
    let s = s0 + u.y * (s1 - s0);
    let w = sqrt(b2) * s / sqrt((1.0 - s) * (1.0 + s));
    let slope = h.g * t + Vec2::new(-h.g.y, h.g.x) * w;
    (slope.x.is_finite() && slope.y.is_finite()).then_some(slope)
}

/// sin(atan(w / b)) = w / sqrt(b^2 + w^2), given b^2.
#[inline]
fn sine_across(w: f32, b2: f32) -> f32 {
    w / sqrt(b2 + w * w)
}

/// Pdf of [`sample_ggx_slope_in`] per unit area of slopes: the marginal a^2 / (2 b^3) over its
/// mass along `g` times the density across, b^2 / ((b^2 + w^2)^(3/2) (s1 - s0)); 0 outside the
/// box.
#[inline]
pub fn ggx_slope_in_pdf(h: &SlopeBox, s: Vec2) -> f32 {
    let t = s.dot(h.g);
    let w = h.g.x * s.y - h.g.y * s.x;
    if !(t >= h.t.x && t <= h.t.y && w >= h.w.x && w <= h.w.y) {
        return 0.0;
    }
    let b2 = h.alpha * h.alpha + t * t;
    let spread = sine_across(h.w.y, b2) - sine_across(h.w.x, b2);
    let q = b2 + w * w;
    let pdf = h.alpha * h.alpha / (2.0 * sqrt(b2) * h.mass * q * sqrt(q) * spread);
    if pdf.is_finite() { pdf } else { 0.0 }
}

/// A reflected direction `wi` (local) off a microfacet whose slope is drawn in the box `h`
/// ([`sample_ggx_slope_in`]), for the local `wo`; `None` when it is not above the surface.
#[inline]
pub fn sample_ggx_reflection_in(wo: Vec3, h: &SlopeBox, u: Vec2) -> Option<Vec3> {
    let s = sample_ggx_slope_in(h, u)?;
    let m = try_normalize(Vec3::new(-s.x, -s.y, 1.0))?;
    let wo_m = dot(wo, m);
    if !(wo_m > 0.0 && wo.z > 0.0) {
        return None;
    }
    let wi = m * (2.0 * wo_m) - wo;
    (wi.z > 0.0).then_some(wi)
}

/// Pdf of [`sample_ggx_reflection_in`] per unit solid angle of `wi`: the slope density over
/// cos^3(theta_m) (slopes to normals) and 4 wo.m (normals to reflected directions).
#[inline]
pub fn ggx_reflection_in_pdf(wo: Vec3, h: &SlopeBox, wi: Vec3) -> f32 {
    if !(wo.z > 0.0 && wi.z > 0.0) {
        return 0.0;
    }
    let Some(m) = try_normalize(wo + wi) else { return 0.0 };
    let wo_m = dot(wo, m);
    if !(m.z > 0.0 && wo_m > 0.0) {
        return 0.0;
    }
    let s = Vec2::new(-m.x / m.z, -m.y / m.z);
    let pdf = ggx_slope_in_pdf(h, s) / (m.z * m.z * m.z * 4.0 * wo_m);
    if pdf.is_finite() { pdf } else { 0.0 }
}

/// An entry drawn from a discrete distribution with 32 random bits (see
/// [`Sampler::next_2d_reusable`](crate::rng::Sampler::next_2d_reusable)), and the bits rescaled
/// within the entry's share: given the entry, `reused` is uniform in [0, 1) and independent of
/// the choice, so it can stand in for a fresh random number (Mitsuba's `sample_reuse`; here
/// exact on the integer grid of the bits).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiscreteSample {
    /// The entry.
    pub index: usize,
    /// Its probability.
    pub probability: f32,
    /// The bits rescaled within the entry's share, in [0, 1).
    pub reused: f32,
}

/// The largest f32 below one.
const ONE_BELOW: f32 = 1.0 - 1.0 / 16_777_216.0;

/// `n` equally likely entries, with their probability 1 / n computed once
/// ([`UniformIndex::sample_reusing`], [`UniformIndex::pmf`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UniformIndex {
    n: usize,
    pmf: f32,
}

impl UniformIndex {
    /// `n` entries (none: nothing is drawn).
    #[inline]
    pub fn new(n: usize) -> Self {
        Self { n, pmf: if n == 0 { 0.0 } else { 1.0 / n as f32 } }
    }

    /// One entry from 32 random bits: the integer part of `bits x n / 2^32`, and its fractional
    /// part as [`DiscreteSample::reused`] (24 bits of it). `None` when there are no entries.
    #[inline]
    pub fn sample_reusing(&self, bits: u32) -> Option<DiscreteSample> {
        let n = self.n;
        if n == 0 {
            return None;
        }
        let scaled = u64::from(bits) * n as u64;
        let index = ((scaled >> 32) as usize).min(n - 1);
        // The top 24 bits of the fraction (built from the bits on the soft-float cores).
        let reused = crate::rng::to_unit(scaled as u32);
        Some(DiscreteSample { index, probability: self.pmf, reused })
    }

    /// The probability of entry `i`: 1 / n for each of the `n` (to within 2^-32 of what
    /// [`UniformIndex::sample_reusing`] realises), 0 beyond.
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        if i < self.n { self.pmf } else { 0.0 }
    }
}

/// How many equally likely values a random number from
/// [`Sampler::next_f32`](crate::rng::Sampler::next_f32) takes: its 24 bits, 2^24.
pub const GRID: u32 = 1 << 24;

/// A discrete distribution on the grid of the random number it is sampled with: entry `i` owns
/// a run of the 2^24 equally likely values of `u`, so the probability [`GridDistribution::pmf`]
/// reports is exactly the one [`GridDistribution::sample`] realises. Every positive weight gets
/// at least one value: a share rounded to none would never be drawn while its pmf still lowered
/// the other technique's MIS weights (a bias).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GridDistribution<const N: usize> {
    /// Where each entry's run of grid values ends (cumulative); empty when no weight is positive.
    ends: heapless::Vec<u32, N>,
}

impl<const N: usize> GridDistribution<N> {
    /// The distribution proportional to `weights` (at most `N` are read); entries whose weight is
    /// not positive get no value. Empty (it samples nothing) when the weights do not have a
    /// positive, finite sum.
    pub fn new(weights: &[f32]) -> Self {
        let mut ends = heapless::Vec::new();
        let weights = weights.get(..N).unwrap_or(weights);
        // The sum of the positive weights (adding zero instead of the others changes no bit of a
        // positive sum, and a sum that is not positive is refused below either way).
        let mut total = 0.0f32;
        for &w in weights {
            total += if w > 0.0 { w } else { 0.0 };
        }
        if !positive_finite(total) {
            return Self { ends };
        }
        // Each share rounded to the grid, at least one value if positive; the rounding difference
        // (at most N values either way) goes to the largest entry, which has at least GRID / N.
        let scale = GRID as f32 / total;
        let mut end = 0u32;
        let mut largest = (0, 0);
        for (i, &w) in weights.iter().enumerate() {
            // Clamped before the conversion (the same value: the share is at least 0.5), so it
            // fits an i32, whose conversion is the cheaper one on x86.
            let c = if w > 0.0 { clamp(w * scale + 0.5, 1.0, GRID as f32) as i32 as u32 } else { 0 };
            end += c;
            if c > largest.1 {
                largest = (i, c);
            }
            // `weights` has at most N entries.
            let _ = ends.push(end);
        }
        // The largest entry's run, and every end after it, moves by the rounding difference.
        let shift = (largest.1 + GRID).saturating_sub(end).wrapping_sub(largest.1);
        for e in ends.iter_mut().skip(largest.0) {
            *e = e.wrapping_add(shift);
        }
        Self { ends }
    }

    /// True when nothing can be sampled (no positive weight).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.ends.last().is_none_or(|&end| end == 0)
    }

    /// The entry owning the grid value of `u` in [0, 1), and its probability.
    #[inline]
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        // u = k / 2^24 exactly for the sampler's numbers; others are clamped into the grid.
        let k = ((u * GRID as f32) as u32).min(GRID - 1);
        self.sample_reusing(k << 8).map(|s| (s.index, s.probability))
    }

    /// The entry owning the grid value of the top 24 of the 32 random `bits` (the value
    /// [`GridDistribution::sample`] takes), its probability, and the bits rescaled within its
    /// run: (value - start + low 8 bits / 256) / (run length).
    #[inline]
    pub fn sample_reusing(&self, bits: u32) -> Option<DiscreteSample> {
        let k = bits >> 8;
        let index = self.ends.iter().position(|&end| k < end)?;
        let (start, end) = self.run(index);
        let count = end - start;
        // Below count x 256 <= 2^32: (k - start) < count <= 2^24.
        let fine = ((k - start) << 8) | (bits & 0xff);
        let reused = (fine as f32 / (count as f32 * 256.0)).min(ONE_BELOW);
        Some(DiscreteSample { index, probability: count as f32 * (1.0 / GRID as f32), reused })
    }

    /// The run of grid values entry `i` owns (empty past the end).
    #[inline]
    fn run(&self, i: usize) -> (u32, u32) {
        let start = match i.checked_sub(1) {
            Some(j) => self.ends.get(j).copied().unwrap_or(0),
            None => 0,
        };
        (start, self.ends.get(i).copied().unwrap_or(start))
    }

    /// The probability of entry `i` under [`GridDistribution::sample`]: its share of the grid.
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        let (start, end) = self.run(i);
        (end - start) as f32 * (1.0 / GRID as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cone_measure_is_exact_for_tiny_spheres() {
        // r/d = 1e-6: 1 - cos = 5e-13 (the naive form gives 0).
        let r_over_d = 1e-6f32;
        let v = cone_one_minus_cos(r_over_d * r_over_d);
        assert!((v / 5e-13 - 1.0).abs() < 1e-5, "{v}");
        assert!(uniform_cone_pdf(v).is_finite());
        // Full hemisphere when the sphere touches the point.
        assert_eq!(cone_one_minus_cos(1.0), 1.0);
    }

    #[test]
    fn cone_samples_stay_inside_the_cone() {
        let omc = cone_one_minus_cos(0.25);
        for i in 0..64 {
            for j in 0..64 {
                let u = Vec2::new(i as f32 / 64.0, j as f32 / 64.0);
                let w = sample_uniform_cone(u, omc);
                assert!(w.z >= 1.0 - omc - 1e-6);
                assert!((w.length() - 1.0).abs() < 1e-5);
            }
        }
    }

    #[test]
    fn spherical_rectangle_samples_invert_to_their_u() {
        // Overhead, off to the side, huge and close, long and thin: sample, then invert.
        let cases = [
            (Vec3::new(-0.5, -0.5, -1.0), 1.0, 1.0),
            (Vec3::new(1.0, 0.3, -0.8), 1.5, 0.7),
            (Vec3::new(-50.0, -50.0, -0.2), 100.0, 100.0),
            (Vec3::new(-20.0, 0.0, -1.0), 40.0, 0.1),
        ];
        let mut worst = 0.0f32;
        for (corner, ex, ey) in cases {
            let r = spherical_rectangle(corner, ex, ey).unwrap();
            for i in 0..33 {
                for j in 0..33 {
                    let u = Vec2::new(i as f32 / 32.0, j as f32 / 32.0) * 0.998 + Vec2::splat(0.001);
                    let p = sample_spherical_rectangle(&r, u).unwrap();
                    let back = invert_spherical_rectangle_sample(&r, p);
                    worst = worst.max((back - u).abs().max_element());
                }
            }
        }
        assert!(worst < 1e-4, "{worst}");
        // The corners of the unit square are the rectangle's corners, in the warp's order.
        let r = spherical_rectangle(Vec3::new(1.0, 0.3, -0.8), 1.5, 0.7).unwrap();
        let n = Vec3::new(0.3, -0.2, -0.9).normalize();
        let w = spherical_rectangle_cosines(&r, n);
        for (k, u) in [(0, Vec2::ZERO), (1, Vec2::X), (2, Vec2::Y), (3, Vec2::ONE)] {
            let p = sample_spherical_rectangle(&r, u * 0.999_999 + Vec2::splat(5e-8)).unwrap();
            let c = n.dot(p) / p.length();
            assert!((c - w[k]).abs() < 1e-3, "corner {k}: {c} vs {}", w[k]);
        }
    }

    #[test]
    fn bilinear_samples_follow_their_pdf() {
        // The pdf integrates to one, and the samples of a 64 x 64 grid of u land with the pdf's
        // mass per quadrant (to the grid's resolution).
        for w in [[0.01, 1.0, 0.5, 0.2], [1.0, 1.0, 1.0, 1.0], [0.0, 0.0, 0.0, 3.0], [0.0; 4]] {
            let n = 200;
            let mut integral = 0.0;
            for i in 0..n {
                for j in 0..n {
                    let p = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    integral += bilinear_pdf(p, w) / (n * n) as f32;
                }
            }
            assert!((integral - 1.0).abs() < 1e-3, "{w:?}: {integral}");
            let mut left = 0.0;
            for i in 0..64 {
                for j in 0..64 {
                    let p = sample_bilinear(Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0), w);
                    assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y), "{w:?}: {p}");
                    left += f32::from(p.x < 0.5) / 4096.0;
                }
            }
            let sum: f32 = w.iter().sum();
            let expected = if sum > 0.0 { (0.75 * (w[0] + w[2]) + 0.25 * (w[1] + w[3])) / sum } else { 0.5 };
            assert!((left - expected).abs() < 0.02, "{w:?}: {left} vs {expected}");
        }
        assert_eq!(bilinear_pdf(Vec2::new(1.5, 0.5), [1.0; 4]), 0.0);
        assert_eq!(sample_linear(0.0, 0.0, 1.0), 0.0);
        assert!(sample_linear(0.999_999_94, 1.0, 0.0) < 1.0);
    }

    /// On a 256 x 256 grid of `u`, the mean of 1 / pdf over the box's samples is the box's
    /// area, and of f / pdf the integral of f over it: the pdf is the samples' density.
    #[test]
    fn slope_box_samples_follow_their_pdf() {
        let n = 256;
        for (alpha, t, w) in [
            (0.02, Vec2::new(0.01, 0.09), Vec2::new(-0.05, 0.04)),
            (0.3, Vec2::new(-0.2, 0.5), Vec2::new(-0.1, 0.3)),
            (1e-3, Vec2::new(0.05, 0.2), Vec2::new(-0.02, 0.02)),
        ] {
            let g = Vec2::new(0.6, -0.8);
            let b = SlopeBox::new(alpha, g, t, w).unwrap();
            let area = (t.y - t.x) * (w.y - w.x);
            // Sums by rows of 256 (f32 only in the kernel): rounding far below the tolerance.
            let (mut inv, mut lin) = (0.0f32, 0.0f32);
            for i in 0..n {
                let (mut inv_row, mut lin_row) = (0.0f32, 0.0f32);
                for j in 0..n {
                    let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    let s = sample_ggx_slope_in(&b, u).unwrap();
                    let pdf = ggx_slope_in_pdf(&b, s);
                    assert!(pdf > 0.0, "{alpha} {s}");
                    inv_row += 1.0 / pdf;
                    lin_row += s.dot(g) / pdf;
                }
                inv += inv_row;
                lin += lin_row;
            }
            let cells = (n * n) as f32;
            let (inv, lin) = (inv / cells, lin / cells);
            // The integral of t over the box: (t1^2 - t0^2) / 2 (w1 - w0).
            let lin_exact = (t.y * t.y - t.x * t.x) / 2.0 * (w.y - w.x);
            assert!((inv / area - 1.0).abs() < 1e-3, "alpha {alpha}: {inv} vs area {area}");
            assert!((lin / lin_exact - 1.0).abs() < 1e-3, "alpha {alpha}: {lin} vs {lin_exact}");
            // Outside the box, nothing.
            assert_eq!(ggx_slope_in_pdf(&b, g * (t.x - 1e-3)), 0.0);
        }
    }

    /// Of the reflected directions of the box `b` seen from `wo`, drawn on a 64 x 64 grid of
    /// `u`, how many `land` (on a light) and how many there are; each has a positive, finite pdf.
    fn lobe_samples_landing(wo: Vec3, b: &SlopeBox, land: impl Fn(Vec3) -> bool) -> (usize, usize) {
        let (mut landed, mut total) = (0, 0);
        for i in 0..64 {
            for j in 0..64 {
                let u = Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0);
                let Some(wi) = sample_ggx_reflection_in(wo, b, u) else { continue };
                total += 1;
                landed += usize::from(land(wi));
                let pdf = ggx_reflection_in_pdf(wo, b, wi);
                assert!(pdf > 0.0 && pdf.is_finite());
            }
        }
        (landed, total)
    }

    /// The lobe samples of the box facing a cone mostly reflect into the cone when the mirror
    /// direction lies just outside its edge (where the lobe alone would mostly miss it).
    #[test]
    fn the_slope_box_faces_the_cone() {
        let wo = Vec3::new(0.3, -0.1, 0.9).normalize();
        let mirror = Vec3::new(-wo.x, -wo.y, wo.z);
        // A cone of half-angle 0.1 whose edge passes 0.01 from the mirror direction.
        let theta = 0.1f32;
        let f = crate::math::Frame::from_normal(mirror);
        let tilt = theta + 0.01;
        let axis = (mirror * tilt.cos() + f.t * tilt.sin()).normalize();
        let alpha = 0.01;
        let b = SlopeBox::facing_cone(wo, alpha, axis, theta.cos(), theta.sin()).unwrap();
        let (inside, total) = lobe_samples_landing(wo, &b, |wi| dot(wi, axis) >= theta.cos());
        // (About three in four: the near side is the edge's tangent, which the edge leaves.)
        assert!(total > 4000 && inside * 10 > total * 6, "{inside} of {total} in the cone");
    }

    /// The box facing a quad's nearest edge: with the mirror direction just outside the edge,
    /// the box starts beyond it and its samples mostly reach the quad; just inside, it holds
    /// the mirror direction; deep inside, it holds a disc of ten alphas (the mixture then stays
    /// off).
    #[test]
    fn the_slope_box_faces_the_quads_nearest_edge() {
        // A near-mirror at the origin; a 2 x 2 quad facing -x at x = 3, from y = 1 to 3 (local z
        // is up: the quad's lower edge is atan(1/3) above the horizon).
        let corners = [
            Vec3::new(3.0, -1.0, 1.0),
            Vec3::new(3.0, 1.0, 1.0),
            Vec3::new(3.0, 1.0, 3.0),
            Vec3::new(3.0, -1.0, 3.0),
        ];
        let mid = |a: Vec3, b: Vec3| (a + b) * 0.5;
        let c = corners;
        let outline =
            [c[0], mid(c[0], c[1]), c[1], mid(c[1], c[2]), c[2], mid(c[2], c[3]), c[3], mid(c[3], c[0])]
                .map(|p| p.normalize());
        let dirs = corners.map(|p| p.normalize());
        let alpha = 0.01;
        let lower = (1.0f32 / 3.0).atan();
        // The mirror direction `above` radians above the lower edge, towards +x.
        let box_at = |above: f32| {
            let t = lower + above;
            let wo = Vec3::new(-t.cos(), 0.0, t.sin());
            let edge = nearest_edge(Vec3::new(-wo.x, -wo.y, wo.z), &dirs).unwrap();
            assert!((edge.sine - above.sin()).abs() < 1e-5, "{above}: {edge:?}");
            (wo, SlopeBox::facing_edge(wo, alpha, &edge, &outline).unwrap())
        };
        let in_quad = |wi: Vec3| {
            let p = wi * (3.0 / wi.x);
            wi.x > 0.0 && p.y.abs() <= 1.0 && (1.0..=3.0).contains(&p.z)
        };
        for above in [-0.005f32, -0.02] {
            let (wo, b) = box_at(above);
            assert!(b.t.x > 0.0 && !b.holds_disc(0.0), "{above}: {b:?}");
            let (inside, total) = lobe_samples_landing(wo, &b, in_quad);
            assert!(total > 4000 && inside * 10 > total * 9, "{above}: {inside} of {total} on the quad");
        }
        let (_, b) = box_at(0.005);
        assert!(b.t.x < 0.0 && b.holds_disc(0.0) && !b.holds_disc(10.0 * alpha), "{b:?}");
        // Halfway up the quad: 0.23 radians from the lower and upper edges' directions, 0.12 in
        // slopes (half the angle).
        let (_, b) = box_at(0.23);
        assert!(b.holds_disc(0.1), "{b:?}");
    }

    #[test]
    fn ggx_is_finite_at_tiny_alpha_and_grazing_angles() {
        let wo = Vec3::new(1.0, 0.0, 1e-6).normalize();
        for alpha in [1e-4f32, 1e-2, 1.0] {
            let m = sample_ggx_vndf(wo, alpha, Vec2::new(0.3, 0.7));
            assert!(m.is_finite() && m.z >= 0.0);
            assert!(ggx_d(m, alpha).is_finite());
            assert!(ggx_vndf_pdf(wo, m, alpha).is_finite());
            assert!(ggx_d(Vec3::Z, alpha).is_finite());
        }
    }

    #[test]
    fn uniform_indices_split_the_bits_into_index_and_remainder() {
        for n in [1usize, 3, 5, 32] {
            let mut count = [0u32; 32];
            // Sums of the reused numbers in units of 2^-24 (exact: they lie on that grid).
            let mut sum = [0u64; 32];
            for j in 0..(1u32 << 16) {
                let uniform = UniformIndex::new(n);
                let s = uniform.sample_reusing(j << 16 | 0x8000).unwrap();
                assert!(s.index < n && (0.0..1.0).contains(&s.reused) && s.probability == 1.0 / n as f32);
                assert!(uniform.pmf(s.index) == s.probability && uniform.pmf(n) == 0.0);
                count[s.index] += 1;
                sum[s.index] += (s.reused * 16_777_216.0) as u64;
            }
            for i in 0..n {
                // Share 1/n within 1e-3, and mean reused number 1/2 within 1e-3.
                let (c, n64) = (u64::from(count[i]), n as u64);
                assert!((c * n64).abs_diff(65_536) * 1000 < 65_536, "n {n}, entry {i}: {c}");
                assert!((2 * sum[i]).abs_diff(c << 24) * 500 < c << 24, "n {n}, entry {i}");
            }
        }
        assert_eq!(UniformIndex::new(0).sample_reusing(7), None);
    }

    #[test]
    fn grid_distributions_realise_their_pmf_exactly() {
        // Shares from 1 down to 1e-14: each positive weight gets at least one grid value.
        let w = [0.0, 1e5, 1e-9, 3.0, 0.0, 1e-3];
        let d = GridDistribution::<6>::new(&w);
        let mut counts = [0u32; 6];
        for k in 0..GRID {
            let (i, p) = d.sample(k as f32 / GRID as f32).unwrap();
            assert_eq!(p, d.pmf(i));
            counts[i] += 1;
        }
        for (i, c) in counts.iter().enumerate() {
            assert_eq!(*c as f32 / GRID as f32, d.pmf(i), "entry {i}");
            assert_eq!(*c > 0, w[i] > 0.0, "entry {i}");
        }
        assert_eq!(counts.iter().sum::<u32>(), GRID);
        // Reuse: within each entry's run the rescaled bits are evenly spread over [0, 1).
        // Sums in units of 2^-24 (exact: the rescaled numbers lie on that grid).
        let mut sums = [0u64; 6];
        for k in 0..GRID {
            let s = d.sample_reusing(k << 8 | 0x80).unwrap();
            assert!((0.0..1.0).contains(&s.reused), "{s:?}");
            assert_eq!((s.index, s.probability), d.sample(k as f32 / GRID as f32).unwrap());
            sums[s.index] += (s.reused * 16_777_216.0) as u64;
        }
        for (i, sum) in sums.iter().enumerate() {
            // Mean 1/2 within 1e-6.
            let n = u64::from(counts[i]);
            assert!(n == 0 || (2 * sum).abs_diff(n << 24) * 500_000 < n << 24, "entry {i}: sum {sum} of {n}");
        }
        assert!(GridDistribution::<2>::new(&[0.0, -1.0]).is_empty());
        assert!(GridDistribution::<2>::new(&[f32::INFINITY, 1.0]).is_empty());
        assert_eq!(GridDistribution::<2>::new(&[0.0]).sample(0.5), None);
        assert_eq!(d.pmf(9), 0.0);
    }
}
