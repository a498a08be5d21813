//! A digest of a render's HDR estimates, to compare two machines bit for bit without moving the
//! images: 64-bit FNV-1a over the f32 bits of every part of every pixel's [`Estimate`]. The
//! firmware logs it, `picomis-sim render --digest` prints it, and the test command compares them.
//!
//! Per pixel, in row-major order (row 0 first), the little-endian bytes of: emitted (r, g, b);
//! light sampling's contribution (r, g, b), weight sum and found count; BSDF sampling's
//! contribution (r, g, b), weight sum and found count. Floats as `f32::to_bits`, so two digests
//! are equal only if every part of every pixel has the same bits (up to hash collisions).

use crate::integrator::{Estimate, Integrator, Strategies, TechniqueEstimate};
use crate::num::Rgb;

/// FNV-1a, 64 bits: offset basis.
const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
/// FNV-1a, 64 bits: prime.
const FNV_PRIME: u64 = 0x0000_0100_0000_01b3;

/// A running 64-bit FNV-1a digest of estimates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Digest(u64);

impl Default for Digest {
    fn default() -> Self {
        Self::new()
    }
}

impl Digest {
    /// The digest of nothing (the FNV offset basis).
    pub const fn new() -> Self {
        Digest(FNV_OFFSET)
    }

    /// Adds the four little-endian bytes of `v`.
    #[inline]
    pub fn push_u32(&mut self, v: u32) {
        for b in v.to_le_bytes() {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(FNV_PRIME);
        }
    }

    fn push_rgb(&mut self, c: Rgb) {
        self.push_u32(c.x.to_bits());
        self.push_u32(c.y.to_bits());
        self.push_u32(c.z.to_bits());
    }

    fn push_technique(&mut self, t: &TechniqueEstimate) {
        self.push_rgb(t.contribution);
        self.push_u32(t.weight_sum.to_bits());
        self.push_u32(t.found);
    }

    /// Adds every part of one pixel's estimate.
    pub fn push(&mut self, e: &Estimate) {
        self.push_rgb(e.emitted);
        self.push_technique(&e.light);
        self.push_technique(&e.bsdf);
    }

    /// The digest so far.
    pub fn value(&self) -> u64 {
        self.0
    }
}

/// The digest of a whole render: [`Integrator::render_pixel`] for every pixel of the film,
/// row-major.
pub fn render_digest<St: Strategies<L>, const S: usize, const L: usize, const M: usize>(
    integrator: &Integrator<'_, St, S, L, M>,
) -> u64 {
    let film = integrator.scene().film();
    let mut d = Digest::new();
    for y in 0..film.height() {
        for x in 0..film.width() {
            d.push(&integrator.render_pixel(x, y));
        }
    }
    d.value()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_64_test_vectors() {
        // Published FNV-1a 64 values: "" and "a".
        assert_eq!(Digest::new().value(), 0xcbf2_9ce4_8422_2325);
        let mut d = Digest::new();
        d.0 = (d.0 ^ u64::from(b'a')).wrapping_mul(FNV_PRIME);
        assert_eq!(d.value(), 0xaf63_dc4c_8601_ec8c);
        // "abcd" as one little-endian word.
        let mut w = Digest::new();
        w.push_u32(u32::from_le_bytes(*b"abcd"));
        let mut b = Digest::new();
        for c in b"abcd" {
            b.0 = (b.0 ^ u64::from(*c)).wrapping_mul(FNV_PRIME);
        }
        assert_eq!(w, b);
    }

    #[test]
    fn every_part_and_every_bit_changes_the_digest() {
        let e = Estimate {
            emitted: Rgb::new(0.5, 0.25, 1.0),
            light: TechniqueEstimate { contribution: Rgb::splat(0.125), weight_sum: 0.75, found: 3 },
            bsdf: TechniqueEstimate { contribution: Rgb::splat(2.0), weight_sum: 0.25, found: 1 },
        };
        let of = |e: &Estimate| {
            let mut d = Digest::new();
            d.push(e);
            d.value()
        };
        let base = of(&e);
        let ulp = |v: f32| f32::from_bits(v.to_bits() + 1);
        let mut variants = [e; 7];
        variants[0].emitted.z = ulp(e.emitted.z);
        variants[1].light.contribution.x = ulp(e.light.contribution.x);
        variants[2].light.weight_sum = ulp(e.light.weight_sum);
        variants[3].light.found += 1;
        variants[4].bsdf.contribution.y = ulp(e.bsdf.contribution.y);
        variants[5].bsdf.weight_sum = ulp(e.bsdf.weight_sum);
        variants[6].bsdf.found += 1;
        for v in &variants {
            assert_ne!(of(v), base, "{v:?}");
        }
        // -0.0 and 0.0 differ in their bits, so they differ here too.
        let mut z = e;
        z.emitted.x = -0.0;
        let mut p = e;
        p.emitted.x = 0.0;
        assert_ne!(of(&z), of(&p));
    }
}
