//! Spherical rectangles: a rectangle seen from a point, sampled uniformly in solid angle, and
//! the cosine warp of those samples.

use crate::num::{INV_PI, Vec2, Vec3, atan2, clamp, finite3, safe_sqrt, sin_cos_turns, sqrt};

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

/// The smallest corner weight of the cosine warp (pbrt-v4's 0.01): corners below the receiver's
/// horizon keep some density, so every direction to the rectangle keeps a positive pdf.
pub const COSINE_WARP_FLOOR: f32 = 0.01;

/// The corner weights of the cosine-warped spherical rectangle (Hart, Pharr, Müller, Lopes,
/// McGuire and Shirley 2020, "Practical Product Sampling by Fitting and Composing Warps"): the
/// receiver's cosines max([`COSINE_WARP_FLOOR`], n . v / |v|) towards the corners (x0, y0),
/// (x1, y0), (x0, y1), (x1, y1), which [`sample_spherical_rectangle`] reaches at u = (0, 0),
/// (1, 0), (0, 1), (1, 1). `n` is the receiver's unit normal in the rectangle's local frame.
/// Warping u by `sample_bilinear` with them draws directions roughly in proportion to the
/// cosine; the pdf is [`spherical_rectangle_pdf`] times `bilinear_pdf` at the u of the
/// direction ([`invert_spherical_rectangle_sample`]).
#[inline]
pub fn spherical_rectangle_cosines(r: &SphericalRectangle, n: Vec3) -> [f32; 4] {
    let cosine = |x: f32, y: f32| {
        let c = cosine_towards(r, n, x, y);
        if c > COSINE_WARP_FLOOR { c } else { COSINE_WARP_FLOOR }
    };
    [cosine(r.x0, r.y0), cosine(r.x1, r.y0), cosine(r.x0, r.y1), cosine(r.x1, r.y1)]
}

/// The cosine between the unit normal `n` and the direction to the point (x, y) of the
/// rectangle's plane (local frame).
#[inline]
fn cosine_towards(r: &SphericalRectangle, n: Vec3, x: f32, y: f32) -> f32 {
    let v = Vec3::new(x, y, r.z0);
    n.dot(v) / sqrt(v.length_squared())
}

/// How much more than the bilinear interpolation of the corners' cosines the cosine may be at
/// an edge's midpoint or the centre of the rectangle for [`fitted_cosine_warp`].
pub const COSINE_WARP_FIT: f32 = 1.25;

/// The corner weights of the cosine warp ([`spherical_rectangle_cosines`]) for the receiver with
/// unit normal `n` (in the rectangle's local frame) where the warp fits its cosine: the cosine
/// towards each edge's midpoint and the centre is at most [`COSINE_WARP_FIT`] times the
/// interpolation of the corners' there; `None` elsewhere. Where the cosine peaks inside the
/// rectangle or on an edge (a floor under a large, close light, or beside the foot of a wall
/// light), the corners understate it, and the warp would draw directions away from where the
/// cosine is largest.
#[inline]
pub fn fitted_cosine_warp(r: &SphericalRectangle, n: Vec3) -> Option<[f32; 4]> {
    let cosine = |x: f32, y: f32| cosine_towards(r, n, x, y);
    let w = spherical_rectangle_cosines(r, n);
    let [c00, c10, c01, c11] = w;
    let (xm, ym) = (0.5 * (r.x0 + r.x1), 0.5 * (r.y0 + r.y1));
    let fits = |c: f32, interpolated: f32| c <= COSINE_WARP_FIT * interpolated;
    let fitted = fits(cosine(xm, r.y0), 0.5 * (c00 + c10))
        && fits(cosine(xm, r.y1), 0.5 * (c01 + c11))
        && fits(cosine(r.x0, ym), 0.5 * (c00 + c01))
        && fits(cosine(r.x1, ym), 0.5 * (c10 + c11))
        && fits(cosine(xm, ym), 0.25 * ((c00 + c10) + (c01 + c11)));
    fitted.then_some(w)
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn the_cosine_warp_fits_where_the_cosine_peaks_at_a_corner() {
        // (corner, edge lengths, receiver normal, whether the warp fits); local frame: the
        // rectangle lies in z = z0 < 0, the receiver at the origin.
        let cases = [
            // A floor under a 4 x 4 light 0.6 above: the cosine is 1 in the middle, 0.2 at the
            // corners.
            (Vec3::new(-2.0, -2.0, -0.6), 4.0, 4.0, Vec3::new(0.0, 0.0, -1.0), false),
            // Beside the foot of a wall light, facing up: the cosine peaks at the bottom edge's
            // middle (0.95) between corners of 0.2.
            (Vec3::new(-1.5, 0.3, -0.1), 3.0, 2.0, Vec3::Y, false),
            // A small light off to the side: the cosine is nearly linear over it.
            (Vec3::new(3.0, 0.0, -1.0), 0.5, 0.5, Vec3::new(0.0, 0.0, -1.0), true),
            // A light overhead, seen at 45 degrees: the peak lies beyond its edge.
            (Vec3::new(0.5, -0.5, -1.0), 1.0, 1.0, Vec3::new(0.0, 0.0, -1.0), true),
        ];
        for (k, (corner, ex, ey, n, fits)) in cases.into_iter().enumerate() {
            let r = spherical_rectangle(corner, ex, ey).unwrap();
            assert_eq!(fitted_cosine_warp(&r, n).is_some(), fits, "case {k}");
            if let Some(w) = fitted_cosine_warp(&r, n) {
                assert_eq!(w, spherical_rectangle_cosines(&r, n));
            }
        }
    }
}
