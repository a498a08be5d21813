//! Under QEMU: the digest of the HDR estimates of the whole film ([`picomis::render_digest`]:
//! 64-bit FNV-1a over the f32 bits of every part of every pixel), logged as `hdr-digest N` for
//! `scripts/firmware.sh test` to compare with `picomis-sim render --digest`. It renders the film
//! a second time, after the framebuffer render; the instruction counts of `measure` time their
//! own loops and do not include it, and board builds (without `qemu`) leave it out.

use crate::board::IntegratorT;

/// Renders every pixel's estimate again and logs the digest.
pub fn report(integrator: &IntegratorT<'_>) {
    let digest = picomis::render_digest(integrator);
    info!("hdr-digest {}", digest);
}
