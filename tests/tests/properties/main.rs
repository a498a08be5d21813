//! Property tests of the kernel on random valid scenes, with proptest on a fixed seed
//! and ChaCha (the same cases on every run, no failure files).
//!
//! A random scene holds a ground (a floor up to 2000 across or a sphere of radius up to 50 under
//! everything) and up to five spheres (radius 1e-4 to 5, some containing the camera or one
//! another) and quads (small, tilted, or floors up to 2000 across), each Lambertian or GGX
//! (alpha 1e-4 to 1) or black, some emitting (radiance 0 or 1e-2 to 1e5), plus up to two point
//! lights (intensity 0 or 1e-2 to 1e3) and a random camera. Settings are random too: every
//! method (power beta 0.25 to 4, cutoff alpha 0 to 1), 0 to 3 samples per technique, 1 to 3
//! camera samples, any seed, sphere lights by area or cone, with and without lobe mixing, every light selection (uniform, by power,
//! by contribution).
//!
//! Properties:
//! 1. `render_pixel` outputs are finite and non-negative everywhere (radiance, emission, both
//!    technique contributions), every technique's weight sum is finite and between 0 and its
//!    number of samples that found light, which is at most spp x its sample count, and a method
//!    using one technique gives each of its samples weight exactly 1.
//! 2. At random points on every shape, for random view directions (a quarter of them grazing,
//!    cos down to 1e-6), for the directions the kernel itself draws (light samples, BSDF samples
//!    traced to an emitter) and for uniform random directions: every pdf (`Material::pdf` and
//!    `eval_pdf`, `BsdfSample::pdf`, `LightSample::pdf`, `Scene::light_pdf`) is finite and
//!    non-negative, sampled ones positive; each technique's pdf is positive wherever the other
//!    one found light it can produce (a light hit by a BSDF ray has a light pdf, a light sample
//!    with f > 0 has a BSDF pdf); re-evaluated at the sample, a light sample's pdf is the
//!    sample's own (exactly for the cone; with lobe mixing, by the light sampler of the settings'
//!    strategies, the mixture's, its lobe part included: a test double whose pdf leaves that part
//!    out fails, `a_mixture_pdf_without_the_lobe_part_fails`) and a BSDF sample's pdf and weight are eval_pdf's (to
//!    the rounding of the direction, see [`check_bsdf_sample`](pdfs::check_bsdf_sample)); the
//!    weights of every heuristic on these q = n p are in [0, 1], 0 where q = 0 and sum to 1
//!    (within 1e-5) wherever some q > 0; and each sample's weighted contribution, computed as the
//!    estimator does, is finite (so the estimator's own filter of non-finite contributions never
//!    has to act).
//! 3. An image depends only on the seed: rendered row-major, in reverse, tile by tile in a
//!    shuffled order, and on 2, 3 and 4 threads taking pixels or tiles as they come, every pixel
//!    has the same bits (every field of its `Estimate`), and the tone-mapped framebuffers written
//!    through `render` and through `render_tile` per shuffled tile on several threads are equal
//!    byte for byte (and equal to `tone_map` of the pixel estimates).
//!
//! Each property also counts what its cases exercised (lit pixels, BSDF rays hitting lights,
//! near-mirror GGX, pdfs re-evaluated, ...) and fails if a count falls below a floor: a change
//! of the generators cannot make it pass vacuously.

mod determinism;
mod finite;
mod pdfs;
mod runner;
mod scenes;
