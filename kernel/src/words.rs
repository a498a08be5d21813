//! A built scene as 32-bit words: what a build script writes on the host
//! ([`Scene::write_image`](crate::Scene::write_image)) and a firmware loads in place
//! ([`Scene::load_image`](crate::Scene::load_image)), so that the device runs none of the code
//! that validates the scene's values and computes what its ray queries cull: the same scene, bit
//! for bit, without that code in flash or its time at boot.
//!
//! Each part writes its values in order ([`Image::put`]) and reads them back ([`Image::get`]);
//! floats as their bits. Reading checks the structure (counts, tags, indices), never trusts a
//! length, and gives `None` on anything else: a damaged image is an error, never a panic.

use crate::num::{Vec2, Vec3};

/// The words of an image being read.
pub(crate) struct Words<'a> {
    words: &'a [u32],
}

impl<'a> Words<'a> {
    /// The reader of `words`.
    pub(crate) fn new(words: &'a [u32]) -> Self {
        Words { words }
    }

    /// The next word.
    #[inline]
    pub(crate) fn u32(&mut self) -> Option<u32> {
        let (&w, rest) = self.words.split_first()?;
        self.words = rest;
        Some(w)
    }

    /// The next word as a count of at most `max`.
    #[inline]
    pub(crate) fn count(&mut self, max: usize) -> Option<usize> {
        usize::try_from(self.u32()?).ok().filter(|&n| n <= max)
    }

    /// The next word as a float.
    #[inline]
    pub(crate) fn f32(&mut self) -> Option<f32> {
        self.u32().map(f32::from_bits)
    }

    /// The next `N` words.
    #[inline]
    pub(crate) fn take<const N: usize>(&mut self) -> Option<[u32; N]> {
        let (head, rest) = self.words.split_first_chunk::<N>()?;
        self.words = rest;
        Some(*head)
    }

    /// Whether every word has been read.
    pub(crate) fn is_empty(&self) -> bool {
        self.words.is_empty()
    }
}

/// The float of word `i` of `a` (`i` a constant below `N`: no bounds check is left).
#[inline(always)]
pub(crate) fn float<const N: usize>(a: &[u32; N], i: usize) -> f32 {
    f32::from_bits(a.get(i).copied().unwrap_or(0))
}

/// The vector of words `i..i + 3` of `a`.
#[inline(always)]
pub(crate) fn vec3<const N: usize>(a: &[u32; N], i: usize) -> Vec3 {
    Vec3::new(float(a, i), float(a, i + 1), float(a, i + 2))
}

/// A part of a built scene that writes itself as words and reads itself back.
pub(crate) trait Image: Sized {
    /// Writes the part's words to `out`.
    fn put(&self, out: &mut dyn FnMut(u32));
    /// Reads the part back; `None` where the words do not hold one.
    fn get(words: &mut Words<'_>) -> Option<Self>;
}

impl Image for u32 {
    fn put(&self, out: &mut dyn FnMut(u32)) {
        out(*self);
    }
    fn get(words: &mut Words<'_>) -> Option<Self> {
        words.u32()
    }
}

impl Image for f32 {
    fn put(&self, out: &mut dyn FnMut(u32)) {
        out(self.to_bits());
    }
    fn get(words: &mut Words<'_>) -> Option<Self> {
        words.f32()
    }
}

impl Image for Vec2 {
    fn put(&self, out: &mut dyn FnMut(u32)) {
        self.x.put(out);
        self.y.put(out);
    }
    fn get(words: &mut Words<'_>) -> Option<Self> {
        Some(Vec2::new(words.f32()?, words.f32()?))
    }
}

impl Image for Vec3 {
    fn put(&self, out: &mut dyn FnMut(u32)) {
        self.x.put(out);
        self.y.put(out);
        self.z.put(out);
    }
    fn get(words: &mut Words<'_>) -> Option<Self> {
        Some(Vec3::new(words.f32()?, words.f32()?, words.f32()?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_read_back_as_written_and_never_past_the_end() {
        let mut out = std::vec::Vec::new();
        let v = Vec3::new(1.5, -0.0, f32::MIN_POSITIVE);
        v.put(&mut |w| out.push(w));
        7u32.put(&mut |w| out.push(w));
        let mut words = Words::new(&out);
        assert_eq!(
            Vec3::get(&mut words).map(|v| v.to_array().map(f32::to_bits)),
            Some(v.to_array().map(f32::to_bits))
        );
        assert_eq!(words.count(6), None); // 7 is more than 6
        assert!(words.is_empty());
        assert_eq!(words.u32(), None);
        assert_eq!(Vec2::get(&mut Words::new(&[1])), None);
    }
}
