//! Boxes of GGX microfacet slopes that reflect towards a light, and the glossy lobe sampled
//! inside one (lobe mixing's samples).

use crate::num::{Vec2, Vec3, dot, positive_finite, sqrt, try_normalize};

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

#[cfg(test)]
mod tests {
    use super::*;

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
        let f = crate::num::Frame::from_normal(mirror);
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
}
