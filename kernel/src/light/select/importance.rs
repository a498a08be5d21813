//! How much light a light may send to a shading point, estimated in O(1) per light from the
//! light alone ([`LightCone`]: the cone of directions it arrives from, its radiance and solid
//! angle), and how much of it the BSDF may reflect towards the viewer. Light selection by
//! contribution ([`LightSelection::Contribution`](crate::light::LightSelection)) picks
//! lights in proportion to a mixture of the two estimates.
//!
//! Both are importances, not bounds, but [`light_importance`] is zero only where the light
//! certainly sends nothing (wholly below the receiver's horizon, the receiver behind a one-sided
//! quad or inside a sphere): with a share of it in the mixture, any light that can contribute
//! keeps a non-zero probability, so selection by it stays unbiased.

use crate::geometry::Shape;
use crate::num::{Frame, PI, Vec3, channel_mean, clamp, finite3, max0, safe_sqrt, sqrt, try_normalize};
use crate::scene::Light;
use crate::scene::{Material, Outgoing};

/// What a point sees of a light: a cone of directions that holds every direction to it, and
/// how bright it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightCone {
    /// Unit direction towards the light's centre.
    pub axis: Vec3,
    /// Sine of the cone's half-angle theta_max (below pi / 2): 0 for a point light; 2 for a cone
    /// of every direction (the point is within a quad light's bounding sphere).
    pub sin_max: f32,
    /// Brightness ([`channel_mean`]) of the radiance times the solid angle, estimated as
    /// pi r^2 / d^2 (spheres) or A cos / d^2 (quads), at most 2 pi; or the brightness of the
    /// intensity over the squared distance (point lights): about the irradiance at normal
    /// incidence.
    pub strength: f32,
    /// Brightness of the radiance (area lights): the reflected radiance is at most this times
    /// the BSDF's albedo. `None` for point lights.
    pub radiance: Option<f32>,
}

/// [`LightCone::sin_max`] of a cone of every direction.
const EVERY_DIRECTION: f32 = 2.0;

/// What [`light_cone`] needs of a light, computed once when the scene is built
/// ([`LightGeometry::new`]): the terms that do not depend on the shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightGeometry {
    /// A point light.
    Point {
        /// Position.
        position: Vec3,
        /// Brightness ([`channel_mean`]) of the intensity (at least 0).
        brightness: f32,
    },
    /// A sphere light.
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius.
        radius: f32,
        /// Its square.
        radius2: f32,
        /// Brightness ([`channel_mean`]) of the radiance (at least 0).
        brightness: f32,
    },
    /// A quad light.
    Quad {
        /// Centroid.
        centroid: Vec3,
        /// Radius of the bounding sphere about the centroid.
        radius: f32,
        /// Its square.
        radius2: f32,
        /// Front normal.
        normal: Vec3,
        /// Area.
        area: f32,
        /// Brightness ([`channel_mean`]) of the radiance (at least 0).
        brightness: f32,
    },
    /// An area light without its shape: it sends nothing anywhere.
    Dark,
}

impl LightGeometry {
    /// The geometry of `light` (emitting from `shape` for area lights).
    pub fn new(light: &Light, shape: Option<&Shape>) -> Self {
        match (*light, shape) {
            (Light::Point { position, intensity }, _) => {
                LightGeometry::Point { position, brightness: max0(channel_mean(intensity)) }
            }
            (Light::Area { .. }, None) => LightGeometry::Dark,
            (Light::Area { radiance, .. }, Some(shape)) => {
                let brightness = max0(channel_mean(radiance));
                let radius = shape.bounding_radius();
                let radius2 = radius * radius;
                match shape.as_sphere() {
                    Some((center, _)) => LightGeometry::Sphere { center, radius, radius2, brightness },
                    None => LightGeometry::Quad {
                        centroid: shape.centroid(),
                        radius,
                        radius2,
                        // A quad's normal is the same at every point.
                        normal: shape.normal_at(shape.centroid()),
                        area: shape.area(),
                        brightness,
                    },
                }
            }
        }
    }

    /// The cone of the light seen from `x`; `None` where it certainly sends nothing to `x` (a
    /// point light at `x`, `x` inside or on a sphere light, or behind a quad light's plane) or
    /// the estimate is not finite. One square root and one division. Always inlined: out of
    /// line, its `Option<LightCone>` went through memory for every light taken one at a time
    /// (x86, selection by contribution on `point_lights`: 5 % of the render time).
    #[inline(always)]
    pub fn cone(&self, x: Vec3) -> Option<LightCone> {
        let cone = match *self {
            LightGeometry::Point { position, brightness } => {
                let v = position - x;
                let d2 = v.length_squared();
                if !(d2 > 0.0) {
                    return None;
                }
                let inv_d = 1.0 / sqrt(d2);
                let strength = brightness * (inv_d * inv_d);
                LightCone { axis: v * inv_d, sin_max: 0.0, strength, radiance: None }
            }
            LightGeometry::Sphere { center, radius, radius2, brightness } => {
                let v = center - x;
                let d2 = v.length_squared();
                if !(d2 > radius2) {
                    // Inside or on a sphere light: its outward front side faces away.
                    return None;
                }
                let inv_d = 1.0 / sqrt(d2);
                let sin_max = radius * inv_d;
                let solid_angle = PI * (sin_max * sin_max);
                let strength = brightness * solid_angle.min(2.0 * PI);
                LightCone { axis: v * inv_d, sin_max, strength, radiance: Some(brightness) }
            }
            LightGeometry::Quad { centroid, radius, radius2, normal, area, brightness } => {
                let v = centroid - x;
                let d2 = v.length_squared();
                let radiance = Some(brightness);
                // A quad emits on the side of its normal only; `x` behind its plane sees none.
                let facing = normal.dot(-v);
                if !(facing > 0.0) {
                    return None;
                }
                if d2 > radius2 {
                    let inv_d = 1.0 / sqrt(d2);
                    let sin_max = radius * inv_d;
                    let solid_angle = (area * facing) * (inv_d * inv_d * inv_d);
                    let strength = brightness * solid_angle.min(2.0 * PI);
                    LightCone { axis: v * inv_d, sin_max, strength, radiance }
                } else {
                    // Within a quad's bounding sphere: up to the whole hemisphere.
                    let axis = try_normalize(v).unwrap_or(Vec3::Z);
                    LightCone { axis, sin_max: EVERY_DIRECTION, strength: brightness * 2.0 * PI, radiance }
                }
            }
            LightGeometry::Dark => return None,
        };
        // A strength beyond f32 (a light at the emission cap seen from very close) is the largest
        // f32: the light keeps the largest share, not none.
        let strength = if cone.strength > f32::MAX { f32::MAX } else { cone.strength };
        (strength.is_finite() && finite3(cone.axis)).then_some(LightCone { strength, ..cone })
    }
}

/// Every light's [`LightGeometry`], in the order of the scene's lights, and on x86 hosts the
/// sphere lights again, four to a packet, for [`LightTable::cones`].
#[derive(Clone, Debug, Default)]
pub struct LightTable<const L: usize> {
    geometry: heapless::Vec<LightGeometry, L>,
    #[cfg(all(not(target_os = "none"), target_feature = "sse"))]
    spheres: heapless::Vec<packed::SpherePacket, L>,
    /// The indices of the lights that are not spheres (x86 hosts: the ones not in a packet).
    #[cfg(all(not(target_os = "none"), target_feature = "sse"))]
    others: heapless::Vec<usize, L>,
}

impl<const L: usize> LightTable<L> {
    /// Adds the next light's geometry; `Err` when the table is full.
    pub fn push(&mut self, geometry: LightGeometry) -> Result<(), LightGeometry> {
        #[cfg(all(not(target_os = "none"), target_feature = "sse"))]
        if let LightGeometry::Sphere { .. } = geometry {
            let index = self.geometry.len();
            if !self.spheres.last_mut().is_some_and(|p| p.add(index, &geometry)) {
                let mut p = packed::SpherePacket::empty();
                p.add(index, &geometry);
                self.spheres.push(p).map_err(|_| geometry)?;
            }
        } else {
            self.others.push(self.geometry.len()).map_err(|_| geometry)?;
        }
        self.geometry.push(geometry)
    }

    /// The lights that [`LightTable::cones`] and [`LightTable::weights`] take one at a time,
    /// with their indices: on x86 hosts those that are not spheres, elsewhere all.
    #[inline]
    fn one_at_a_time(&self) -> impl Iterator<Item = (usize, &LightGeometry)> {
        #[cfg(all(not(target_os = "none"), target_feature = "sse"))]
        return self.others.iter().filter_map(|&k| self.geometry.get(k).map(|g| (k, g)));
        #[cfg(not(all(not(target_os = "none"), target_feature = "sse")))]
        self.geometry.iter().enumerate()
    }

    /// Every light's geometry.
    #[inline]
    pub fn geometry(&self) -> &[LightGeometry] {
        &self.geometry
    }

    /// Calls `f(k, cone, importance)` for light `k`, in some order, for every light whose cone
    /// seen from `x` exists ([`LightGeometry::cone`]), with its importance at the receiver's
    /// unit normal `n` ([`LightCone::importance`]): the same values, bit for bit, whether the
    /// sphere lights go four at a time (x86 hosts) or one at a time.
    #[inline]
    pub fn cones(&self, x: Vec3, n: Vec3, mut f: impl FnMut(usize, &LightCone, f32)) {
        for (k, g) in self.one_at_a_time() {
            if let Some(cone) = g.cone(x) {
                f(k, &cone, cone.importance(n));
            }
        }
        #[cfg(all(not(target_os = "none"), target_feature = "sse"))]
        for p in &self.spheres {
            p.cones(x, n, &mut f);
        }
    }

    /// Calls `f(k, importance, contribution)` for light `k`, in some order, for every light
    /// whose cone seen from `x` exists, like [`LightTable::cones`]: its importance at the unit
    /// normal `n` and its contribution to `receiver` ([`LightCone::contribution_to`]; 0 without
    /// one). The same values, bit for bit, whether the sphere lights go four at a time (x86
    /// hosts, GGX receivers in the lanes too) or one at a time.
    #[inline]
    pub fn weights(&self, x: Vec3, n: Vec3, receiver: Option<&Receiver>, mut f: impl FnMut(usize, f32, f32)) {
        for (k, g) in self.one_at_a_time() {
            if let Some(cone) = g.cone(x) {
                f(k, cone.importance(n), receiver.map_or(0.0, |r| cone.contribution_to(r)));
            }
        }
        // A loop of its own for GGX receivers: what the lanes need of the receiver is set up
        // for them only.
        #[cfg(all(not(target_os = "none"), target_feature = "sse"))]
        match receiver.map(|r| (r, *r.bsdf.material())) {
            Some((r, Material::GgxConductor { alpha, reflectance })) => {
                for p in &self.spheres {
                    p.weights_ggx(x, n, r, alpha, reflectance, &mut f);
                }
            }
            _ => {
                for p in &self.spheres {
                    p.weights(x, n, receiver, &mut f);
                }
            }
        }
    }
}

/// Sphere lights four at a time, with the operations of [`LightGeometry::cone`] and
/// [`LightCone::importance`] in the same order in each lane: IEEE add, multiply, divide and
/// square root round the same in a lane as in a scalar, so the bits are the same.
#[cfg(all(not(target_os = "none"), target_feature = "sse"))]
mod packed {
    use wide::{CmpEq, CmpGe, CmpGt, CmpLe, CmpLt, CmpNe, f32x4};

    use super::{LightCone, LightGeometry, Receiver};
    use crate::num::{PI, Rgb, Vec3};

    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct SpherePacket {
        c: [f32x4; 3],
        radius: f32x4,
        /// r^2; +infinity in an empty lane, which no point is outside of.
        radius2: f32x4,
        brightness: f32x4,
        index: [usize; 4],
        len: usize,
    }

    /// All-ones lanes where `v` is finite: `v - v` is zero exactly there, NaN elsewhere (two
    /// instructions, against four for `f32x4::is_finite`).
    #[inline(always)]
    #[allow(clippy::eq_op)]
    fn finite(v: f32x4) -> f32x4 {
        (v - v).cmp_eq(f32x4::ZERO)
    }

    impl SpherePacket {
        /// A packet of empty lanes.
        pub fn empty() -> Self {
            SpherePacket {
                c: [f32x4::ZERO; 3],
                radius: f32x4::ZERO,
                radius2: f32x4::splat(f32::INFINITY),
                brightness: f32x4::ZERO,
                index: [0; 4],
                len: 0,
            }
        }

        /// Puts light `index` in the next lane; false when the packet is full.
        pub fn add(&mut self, index: usize, g: &LightGeometry) -> bool {
            let (LightGeometry::Sphere { center, radius, radius2, brightness }, true) = (*g, self.len < 4)
            else {
                return false;
            };
            let k = self.len;
            let set = |v: &mut f32x4, x: f32| {
                let mut a = v.to_array();
                a[k] = x;
                *v = f32x4::from(a);
            };
            set(&mut self.c[0], center.x);
            set(&mut self.c[1], center.y);
            set(&mut self.c[2], center.z);
            set(&mut self.radius, radius);
            set(&mut self.radius2, radius2);
            set(&mut self.brightness, brightness);
            self.index[k] = index;
            self.len += 1;
            true
        }

        /// The cones of the packet's lights seen from `x` and their importances at `n`, with
        /// the mask of the lanes whose cone exists; `None` where none does.
        #[inline]
        fn lanes(&self, x: Vec3, n: Vec3) -> Option<Lanes> {
            let vx = self.c[0] - f32x4::splat(x.x);
            let vy = self.c[1] - f32x4::splat(x.y);
            let vz = self.c[2] - f32x4::splat(x.z);
            let d2 = vx * vx + vy * vy + vz * vz;
            let outside = d2.cmp_gt(self.radius2);
            let inv_d = f32x4::ONE / d2.sqrt();
            let sin_max = self.radius * inv_d;
            let solid_angle = f32x4::splat(PI) * (sin_max * sin_max);
            // f32::min against a number: the number where `solid_angle` is NaN.
            let two_pi = f32x4::splat(2.0 * PI);
            let strength = self.brightness * solid_angle.cmp_lt(two_pi).blend(solid_angle, two_pi);
            let (ax, ay, az) = (vx * inv_d, vy * inv_d, vz * inv_d);
            let ok = outside & finite(strength) & finite(ax) & finite(ay) & finite(az);
            let mask = ok.move_mask();
            if mask == 0 {
                return None;
            }
            // LightCone::importance: strength times clamp(n . axis + sin_max, 0, 1), 0 unless finite.
            let v = f32x4::splat(n.x) * ax + f32x4::splat(n.y) * ay + f32x4::splat(n.z) * az + sin_max;
            let cosine = v.cmp_lt(f32x4::ZERO).blend(f32x4::ZERO, v.cmp_gt(f32x4::ONE).blend(f32x4::ONE, v));
            let importance = strength * cosine;
            let importance = finite(importance).blend(importance, f32x4::ZERO);
            Some(Lanes { axis: [ax, ay, az], sin_max, strength, importance, mask })
        }

        /// Lane `k`'s cone.
        #[inline]
        fn cone(&self, lanes: &Lanes, k: usize) -> LightCone {
            let [ax, ay, az] = lanes.axis.map(|a| a.to_array());
            LightCone {
                axis: Vec3::new(ax[k], ay[k], az[k]),
                sin_max: lanes.sin_max.to_array()[k],
                strength: lanes.strength.to_array()[k],
                radiance: Some(self.brightness.to_array()[k]),
            }
        }

        /// [`super::LightTable::cones`] for the lights of this packet.
        #[inline]
        pub fn cones(&self, x: Vec3, n: Vec3, f: &mut impl FnMut(usize, &LightCone, f32)) {
            let Some(lanes) = self.lanes(x, n) else { return };
            let importance = lanes.importance.to_array();
            for (k, (&index, &importance)) in self.index.iter().zip(&importance).enumerate().take(self.len) {
                if lanes.mask & (1 << k) != 0 {
                    f(index, &self.cone(&lanes, k), importance);
                }
            }
        }

        /// [`super::LightTable::weights`] for the lights of this packet, the contributions
        /// one lane at a time (see [`SpherePacket::weights_ggx`] for GGX receivers).
        #[inline]
        pub fn weights(
            &self,
            x: Vec3,
            n: Vec3,
            receiver: Option<&Receiver>,
            f: &mut impl FnMut(usize, f32, f32),
        ) {
            let Some(lanes) = self.lanes(x, n) else { return };
            let importance = lanes.importance.to_array();
            for (k, (&index, &importance)) in self.index.iter().zip(&importance).enumerate().take(self.len) {
                if lanes.mask & (1 << k) != 0 {
                    let contribution = receiver.map_or(0.0, |r| self.cone(&lanes, k).contribution_to(r));
                    f(index, importance, contribution);
                }
            }
        }

        /// [`super::LightTable::weights`] for the lights of this packet and the GGX receiver
        /// `r` (`alpha`, `reflectance`), the contributions in the lanes ([`ggx_contributions`]).
        #[inline]
        pub fn weights_ggx(
            &self,
            x: Vec3,
            n: Vec3,
            r: &Receiver,
            alpha: f32,
            reflectance: Rgb,
            f: &mut impl FnMut(usize, f32, f32),
        ) {
            let Some(lanes) = self.lanes(x, n) else { return };
            let importance = lanes.importance.to_array();
            let contribution = ggx_contributions(r, alpha, reflectance, &lanes, self.brightness).to_array();
            for (k, ((&index, &importance), &contribution)) in
                self.index.iter().zip(&importance).zip(&contribution).enumerate().take(self.len)
            {
                if lanes.mask & (1 << k) != 0 {
                    f(index, importance, contribution);
                }
            }
        }
    }

    /// A packet's cones seen from a point: axes, sines of the half-angles, strengths,
    /// importances, and the mask of the lanes whose cone exists.
    struct Lanes {
        axis: [f32x4; 3],
        sin_max: f32x4,
        strength: f32x4,
        importance: f32x4,
        mask: i32,
    }

    /// `v` where it is positive, else 0 ([`crate::num::max0`]).
    #[inline(always)]
    fn max0(v: f32x4) -> f32x4 {
        v.cmp_gt(f32x4::ZERO).blend(v, f32x4::ZERO)
    }

    /// [`LightCone::contribution_to`] of every lane's cone (radiance `brightness`) to the GGX
    /// receiver `r` (`alpha`, `reflectance`): [`super::nearest_in_cone`], then
    /// [`Outgoing::eval`](crate::scene::Outgoing::eval) with [`crate::sampling::ggx_d`] and
    /// [`crate::sampling::ggx_g1`], with the same operations in the same order; each branch
    /// is computed in every lane and the scalar code's choice blended in.
    #[inline]
    fn ggx_contributions(
        r: &Receiver,
        alpha: f32,
        reflectance: Rgb,
        lanes: &Lanes,
        brightness: f32x4,
    ) -> f32x4 {
        let s = f32x4::splat;
        let (zero, one) = (f32x4::ZERO, f32x4::ONE);
        let [ax, ay, az] = lanes.axis;
        let sin_max = lanes.sin_max;
        // The axis in the receiver's frame (Frame::to_local).
        let (t, b, nn) = (r.frame.t, r.frame.b, r.frame.n);
        let lx = ax * s(t.x) + ay * s(t.y) + az * s(t.z);
        let ly = ax * s(b.x) + ay * s(b.y) + az * s(b.z);
        let lz = ax * s(nn.x) + ay * s(nn.y) + az * s(nn.z);
        // nearest_in_cone(l, sin_max, lobe).
        let lobe = r.lobe;
        let cos_a = lx * s(lobe.x) + ly * s(lobe.y) + lz * s(lobe.z);
        let cos_max = max0(one - sin_max * sin_max).sqrt();
        let (vx, vy, vz) = (s(lobe.x) - lx * cos_a, s(lobe.y) - ly * cos_a, s(lobe.z) - lz * cos_a);
        let len2 = vx * vx + vy * vy + vz * vz;
        let normalizes = len2.cmp_gt(zero) & finite(len2);
        let inv = one / len2.sqrt();
        let turned = |l: f32x4, v: f32x4| normalizes.blend(l * cos_max + (v * inv) * sin_max, l);
        let lobe_itself = sin_max.cmp_ge(one) | cos_a.cmp_ge(cos_max);
        let wx = lobe_itself.blend(s(lobe.x), turned(lx, vx));
        let wy = lobe_itself.blend(s(lobe.y), turned(ly, vy));
        let wz = lobe_itself.blend(s(lobe.z), turned(lz, vz));
        // Outgoing::eval(w): zero unless wo and w are above the horizon and wo + w normalizes.
        let wo = r.bsdf.wo();
        let (hx, hy, hz) = (s(wo.x) + wx, s(wo.y) + wy, s(wo.z) + wz);
        let h2 = hx * hx + hy * hy + hz * hz;
        let inv_h = one / h2.sqrt();
        let (mx, my, mz) = (hx * inv_h, hy * inv_h, hz * inv_h);
        // ggx_d(m, alpha).
        let a2 = alpha * alpha;
        let tm = (mx * mx + my * my) / s(a2) + mz * mz;
        let d = mz.cmp_le(zero).blend(zero, one / (s(PI * a2) * tm * tm));
        // ggx_g1(w, alpha) (w.z > 0 where it is used).
        let g1 = (wz + wz) / (wz + (s(a2) + s(1.0 - a2) * (wz * wz)).sqrt());
        let q = (d * s(r.bsdf.pdf_scale())) * g1;
        let lum = (s(reflectance.x) * q + s(reflectance.y) * q + s(reflectance.z) * q) * s(1.0 / 3.0);
        let black = s(wo.z).cmp_le(zero) | wz.cmp_le(zero) | !(h2.cmp_gt(zero) & finite(h2));
        let lum = black.blend(zero, lum);
        // strength times max0(channel mean), at most the radiance times the albedo bound
        // (f32::min: the bound where the estimate is NaN, the estimate where the bound is).
        let estimate = lanes.strength * max0(lum);
        let cap = brightness * s(r.albedo);
        let estimate = cap.cmp_ne(cap).blend(estimate, estimate.cmp_lt(cap).blend(estimate, cap));
        finite(estimate).blend(estimate, zero)
    }
}

/// The cone of `light` (emitting from `shape` for area lights) seen from `x`
/// ([`LightGeometry::cone`]).
#[inline]
pub fn light_cone(light: &Light, shape: Option<&Shape>, x: Vec3) -> Option<LightCone> {
    LightGeometry::new(light, shape).cone(x)
}

/// The direction of the cone of `sin_max` around unit `axis` nearest to unit `t`: `t` itself
/// inside the cone, else the axis turned towards `t` by the half-angle.
#[inline]
fn nearest_in_cone(axis: Vec3, sin_max: f32, t: Vec3) -> Vec3 {
    if sin_max >= 1.0 {
        return t;
    }
    let cos_a = axis.dot(t);
    let cos_max = safe_sqrt(1.0 - sin_max * sin_max);
    if cos_a >= cos_max {
        return t;
    }
    match try_normalize(t - axis * cos_a) {
        Some(side) => axis * cos_max + side * sin_max,
        None => axis,
    }
}

/// Whether selection by contribution weighs lights by `bsdf` beyond their importance: not for a
/// Lambertian receiver, whose f cos is albedo / pi times the cosine the importance already has.
#[inline]
pub fn weighs_bsdf(bsdf: &Material) -> bool {
    !matches!(bsdf, Material::Lambertian { .. })
}

impl LightCone {
    /// The importance at a receiver with unit normal `n`: strength times min(1, cos theta +
    /// sin theta_max), theta the angle between `n` and the axis: about the largest receiver
    /// cosine in the cone, and zero exactly when the cone is wholly below the horizon
    /// (theta >= pi / 2 + theta_max). No square root.
    #[inline]
    pub fn importance(&self, n: Vec3) -> f32 {
        let cosine = clamp(n.dot(self.axis) + self.sin_max, 0.0, 1.0);
        let importance = self.strength * cosine;
        if importance.is_finite() { importance } else { 0.0 }
    }

    /// The estimated reflected radiance towards `wo` (local, in `frame`) of a receiver with
    /// `bsdf`: strength times f cos (brightness) in the direction of the cone nearest the BSDF's
    /// lobe axis ([`Material::lobe_axis`]), at most the radiance times the albedo bound. Zero
    /// where that direction is below the horizon, though other directions of the cone may not
    /// be: not a bound (see [`weighs_bsdf`] for Lambertian receivers).
    #[inline]
    pub fn contribution(&self, bsdf: &Material, frame: &Frame, wo: Vec3) -> f32 {
        self.contribution_to(&Receiver::new(&bsdf.seen_from(wo), frame))
    }

    /// [`LightCone::contribution`] to `receiver`, whose terms are computed once for all lights.
    #[inline]
    pub fn contribution_to(&self, receiver: &Receiver) -> f32 {
        let w = nearest_in_cone(receiver.frame.to_local(self.axis), self.sin_max, receiver.lobe);
        let estimate = self.strength * max0(channel_mean(receiver.bsdf.eval(w)));
        let estimate = match self.radiance {
            Some(le) => estimate.min(le * receiver.albedo),
            None => estimate,
        };
        // Beyond f32 (a near-mirror's peak times a light at the cap): the largest f32.
        if estimate.is_finite() {
            estimate
        } else if estimate > 0.0 {
            f32::MAX
        } else {
            0.0
        }
    }
}

/// A receiver as [`LightCone::contribution_to`] sees it: its frame, its BSDF seen from `wo`,
/// the lobe axis and the brightness of the albedo bound.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Receiver {
    frame: Frame,
    bsdf: Outgoing,
    lobe: Vec3,
    albedo: f32,
}

impl Receiver {
    /// The receiver with the BSDF `seen` from its `wo` (local, in `frame`).
    #[inline]
    pub fn new(seen: &Outgoing, frame: &Frame) -> Self {
        let bsdf = seen.material();
        Receiver {
            frame: *frame,
            bsdf: *seen,
            lobe: bsdf.lobe_axis(seen.wo()),
            albedo: max0(channel_mean(bsdf.albedo_bound())),
        }
    }
}

/// The importance of `light` (emitting from `shape` for area lights) at point `x` with unit
/// normal `n`: brightness of the radiance times the subtended solid angle times the largest
/// receiver cosine (spheres and quads), or brightness of the intensity over the squared distance
/// times the receiver cosine (point lights). Finite and non-negative.
pub fn light_importance(light: &Light, shape: Option<&Shape>, x: Vec3, n: Vec3) -> f32 {
    light_cone(light, shape, x).map_or(0.0, |cone| cone.importance(n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::num::Rgb;

    /// A 2 x 2 quad at height 2 facing down.
    fn ceiling_quad() -> Shape {
        Shape::quad([
            Vec3::new(-1.0, 2.0, -1.0),
            Vec3::new(1.0, 2.0, -1.0),
            Vec3::new(1.0, 2.0, 1.0),
            Vec3::new(-1.0, 2.0, 1.0),
        ])
        .unwrap()
    }

    fn area(shape: &Shape, l: f32) -> (Light, Shape) {
        (Light::Area { shape: crate::scene::ShapeId::new(0), radiance: Rgb::splat(l) }, *shape)
    }

    #[test]
    fn a_sphere_overhead_gives_radiance_times_solid_angle() {
        let s = Shape::sphere(Vec3::new(0.0, 10.0, 0.0), 1.0).unwrap();
        let (light, shape) = area(&s, 3.0);
        let got = light_importance(&light, Some(&shape), Vec3::ZERO, Vec3::Y);
        // pi r^2 / d^2 is the cone's solid angle to 0.3 %.
        let omega = 2.0 * PI * (1.0 - (1.0f32 - 0.01).sqrt());
        assert!((got / (3.0 * omega) - 1.0).abs() < 3e-3, "{got}");
        // Twice as far: about a quarter.
        let s2 = Shape::sphere(Vec3::new(0.0, 20.0, 0.0), 1.0).unwrap();
        let far = light_importance(&light, Some(&s2), Vec3::ZERO, Vec3::Y);
        assert!((got / far - 4.0).abs() < 0.01, "{}", got / far);
    }

    #[test]
    fn zero_only_where_the_light_cannot_contribute() {
        let s = Shape::sphere(Vec3::new(3.0, 0.5, 0.0), 1.0).unwrap();
        let (light, shape) = area(&s, 1.0);
        // Partly above the horizon (centre 0.5 above, radius 1): positive.
        assert!(light_importance(&light, Some(&shape), Vec3::ZERO, Vec3::Y) > 0.0);
        // Wholly below: zero.
        let below = Shape::sphere(Vec3::new(3.0, -1.5, 0.0), 1.0).unwrap();
        assert_eq!(light_importance(&light, Some(&below), Vec3::ZERO, Vec3::Y), 0.0);
        // Inside: zero.
        assert_eq!(light_importance(&light, Some(&shape), Vec3::new(3.0, 0.5, 0.2), Vec3::Y), 0.0);
        // A ceiling quad facing down: seen from below, not from above.
        let q = ceiling_quad();
        assert!(q.normal_at(Vec3::ZERO).y < 0.0);
        let (ql, qs) = area(&q, 1.0);
        let under = light_importance(&ql, Some(&qs), Vec3::ZERO, Vec3::Y);
        // Far below, about L A / d^2.
        let far = light_importance(&ql, Some(&qs), Vec3::new(0.0, -98.0, 0.0), Vec3::Y);
        assert!((far / (4.0 / 10_000.0) - 1.0).abs() < 1e-3, "{far}");
        assert!(under > far);
        assert_eq!(light_importance(&ql, Some(&qs), Vec3::new(0.0, 3.0, 0.0), Vec3::Y), 0.0);
        // Close to the quad: capped at the hemisphere.
        let close = light_importance(&ql, Some(&qs), Vec3::new(0.0, 1.9, 0.0), Vec3::Y);
        assert!((close - 2.0 * PI).abs() < 1e-5, "{close}");
        // A quad beside a receiver whose horizon cuts it: positive.
        let side = light_importance(&ql, Some(&qs), Vec3::new(3.0, 1.9, 0.0), Vec3::Y);
        assert!(side > 0.0);
        // Point lights: I cos / d^2, zero below the horizon.
        let p = Light::Point { position: Vec3::new(0.0, 2.0, 0.0), intensity: Rgb::splat(8.0) };
        assert!((light_importance(&p, None, Vec3::ZERO, Vec3::Y) - 2.0).abs() < 1e-6);
        assert_eq!(light_importance(&p, None, Vec3::ZERO, -Vec3::Y), 0.0);
        assert_eq!(light_importance(&p, None, Vec3::new(0.0, 2.0, 0.0), Vec3::Y), 0.0);
    }

    #[test]
    fn the_receiver_cosine_is_about_that_of_the_cone_edge_nearest_the_normal() {
        let cone = |deg: f32, half: f32| LightCone {
            axis: Vec3::new(deg.to_radians().sin(), deg.to_radians().cos(), 0.0),
            sin_max: half.to_radians().sin(),
            strength: 1.0,
            radiance: None,
        };
        // Cone axis 60 degrees off the normal, half-angle 20: the edge is 40 degrees off.
        let c = cone(60.0, 20.0).importance(Vec3::Y);
        assert!((c / 40f32.to_radians().cos() - 1.0).abs() < 0.15, "{c}");
        // Half-angle 60: the cone holds the normal.
        assert_eq!(cone(60.0, 60.0).importance(Vec3::Y), 1.0);
        // Axis 120 degrees off, half-angle 20 (wholly below) or 40 (partly above).
        assert_eq!(cone(120.0, 20.0).importance(Vec3::Y), 0.0);
        assert!(cone(120.0, 40.0).importance(Vec3::Y) > 0.0);
        // Every direction.
        let mut every = cone(180.0, 0.0);
        every.sin_max = EVERY_DIRECTION;
        assert_eq!(every.importance(Vec3::Y), 1.0);
    }

    /// `N` lights in a table and as an array: a point light (index 2), a quad light (index 5)
    /// and sphere lights of radius `r0 + dr k` elsewhere.
    fn mixed_table<const N: usize>(r0: f32, dr: f32) -> (LightTable<N>, [LightGeometry; N]) {
        let mut table: LightTable<N> = LightTable::default();
        let mut lights = [LightGeometry::Dark; N];
        let q = ceiling_quad();
        for (k, slot) in lights.iter_mut().enumerate() {
            let g = match k {
                2 => LightGeometry::new(
                    &Light::Point { position: Vec3::ONE, intensity: Rgb::splat(3.0) },
                    None,
                ),
                5 => LightGeometry::new(&area(&q, 2.0).0, Some(&q)),
                _ => {
                    let c = Vec3::new(k as f32 - 3.0, 0.5 * k as f32, 0.25);
                    let s = Shape::sphere(c, r0 + dr * k as f32).unwrap();
                    LightGeometry::new(&area(&s, 1.0 + k as f32).0, Some(&s))
                }
            };
            *slot = g;
            table.push(g).unwrap();
        }
        (table, lights)
    }

    #[test]
    fn the_table_gives_each_light_its_cone_bit_for_bit() {
        // Six spheres (two packets on x86 hosts, one half empty), a point light and a quad,
        // seen from points around, on and inside them: the table's cones and importances are
        // the scalar ones.
        let (table, lights) = mixed_table::<8>(0.1, 0.3);
        assert_eq!(table.geometry(), &lights);
        let mut seen = 0;
        for i in 0..400 {
            let t = i as f32 * 0.37;
            let x = Vec3::new(4.0 * libm::sinf(t), 3.0 * libm::cosf(1.3 * t), 2.0 * libm::sinf(0.7 * t));
            let n = Vec3::new(libm::cosf(t), 0.5, libm::sinf(2.0 * t)).normalize();
            let mut got = [None; 8];
            table.cones(x, n, |k, cone, importance| got[k] = Some((*cone, importance.to_bits())));
            for (k, g) in lights.iter().enumerate() {
                let want = g.cone(x).map(|c| (c, c.importance(n).to_bits()));
                assert_eq!(got[k], want, "light {k} from {x}");
                seen += usize::from(want.is_some());
            }
        }
        // Most lights are seen, some not (inside a sphere, behind the quad).
        assert!(seen > 2000 && seen < 3200, "{seen}");
    }

    #[test]
    fn the_table_gives_each_light_its_contribution_bit_for_bit() {
        // Seven spheres (two packets on x86 hosts), some large and close (cones that hold the
        // lobe, or sin_max near 1), a point light and a quad, from points and normals around
        // them, to GGX receivers from near-mirror to rough, seen from above and below the
        // horizon, and to a Lambertian one: the table's weights are the scalar ones.
        let (table, lights) = mixed_table::<9>(0.01, 0.4);
        let materials = [
            Material::ggx_conductor(1e-4, Rgb::ONE).unwrap(),
            Material::ggx_conductor(0.005, Rgb::new(1.0, 0.5, 0.25)).unwrap(),
            Material::ggx_conductor(0.1, Rgb::splat(0.8)).unwrap(),
            Material::ggx_conductor(1.0, Rgb::new(0.0, 0.3, 1.0)).unwrap(),
            Material::lambertian(Rgb::splat(0.5)).unwrap(),
        ];
        let (mut seen, mut positive) = (0, 0);
        for i in 0..2000 {
            let t = i as f32 * 0.37;
            let x = Vec3::new(4.0 * libm::sinf(t), 3.0 * libm::cosf(1.3 * t), 2.0 * libm::sinf(0.7 * t));
            let n = Vec3::new(libm::cosf(t), 0.5, libm::sinf(2.0 * t)).normalize();
            let frame = Frame::from_normal(n);
            // Mostly above the horizon, sometimes below or grazing.
            let wo = Vec3::new(libm::sinf(2.3 * t), libm::cosf(0.9 * t), libm::sinf(1.7 * t) + 0.3);
            let wo = match i % 7 {
                0 => Vec3::new(wo.x, wo.y, 0.0),
                _ => wo.normalize(),
            };
            let bsdf = materials[i % materials.len()];
            let receiver = Receiver::new(&bsdf.seen_from(wo), &frame);
            let receiver = if i % 11 == 0 { None } else { Some(&receiver) };
            let mut got = [None; 9];
            table.weights(x, n, receiver, |k, importance, c| {
                got[k] = Some((importance.to_bits(), c.to_bits()))
            });
            for (k, g) in lights.iter().enumerate() {
                let want = g.cone(x).map(|cone| {
                    let c = receiver.map_or(0.0, |r| cone.contribution_to(r));
                    (cone.importance(n).to_bits(), c.to_bits())
                });
                assert_eq!(got[k], want, "light {k} from {x}, {bsdf:?} seen from {wo}");
                seen += usize::from(want.is_some());
                positive += usize::from(want.is_some_and(|(_, c)| f32::from_bits(c) > 0.0));
            }
        }
        assert!(seen > 8000 && positive > 2000, "{seen} {positive}");
    }

    #[test]
    fn the_bsdf_weighs_the_light_nearest_its_lobe() {
        use crate::scene::Material;
        // A near-mirror receiver at the origin; wo mirrors to the direction of light a.
        let wo_world = Vec3::new(-1.0, 1.0, 0.0).normalize();
        let frame = Frame::from_normal(Vec3::Y);
        let wo = frame.to_local(wo_world);
        let ggx = Material::ggx_conductor(0.01, Rgb::splat(0.9)).unwrap();
        let a = Shape::sphere(Vec3::new(3.0, 3.0, 0.0), 0.3).unwrap();
        let b = Shape::sphere(Vec3::new(-3.0, 3.0, 0.0), 0.3).unwrap();
        let (la, sa) = area(&a, 1.0);
        let (lb, sb) = area(&b, 1.0);
        let ca = light_cone(&la, Some(&sa), Vec3::ZERO).unwrap();
        let cb = light_cone(&lb, Some(&sb), Vec3::ZERO).unwrap();
        // Equal importance, very different contributions.
        assert!((ca.importance(Vec3::Y) / cb.importance(Vec3::Y) - 1.0).abs() < 1e-5);
        let (fa, fb) = (ca.contribution(&ggx, &frame, wo), cb.contribution(&ggx, &frame, wo));
        assert!(fa > 1e3 * fb && fb > 0.0, "{fa} {fb}");
        // The mirror direction misses light a's centre but meets its edge: still the peak, capped
        // at radiance x reflectance.
        let edge = Shape::sphere(Vec3::new(3.0, 3.0, 0.25), 0.3).unwrap();
        let (le, se) = area(&edge, 1.0);
        let ce = light_cone(&le, Some(&se), Vec3::ZERO).unwrap();
        assert!(ce.contribution(&ggx, &frame, wo) >= 0.5 * fa, "{}", ce.contribution(&ggx, &frame, wo));
        assert!(fa <= 0.9 * channel_mean(Rgb::ONE) + 1e-6);
        assert!(weighs_bsdf(&ggx) && !weighs_bsdf(&Material::lambertian(Rgb::ONE).unwrap()));
    }
}
