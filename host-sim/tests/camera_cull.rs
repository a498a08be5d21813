//! Camera-ray culling by film tile (`picomis::camera_cull`) on every built-in scene: for every
//! pixel of several film sizes (the firmware's 64x48 among them), at the pixel's corners and at
//! jittered points inside it, the culled query `Scene::intersect_camera` returns the hit of the
//! full query `Scene::intersect`, bit for bit (distance, object, point, normal, side). The check is
//! not vacuous: most rays hit something, and the tiles cull most of the Veach scene's objects.

use picomis::{Arith, Film, Sampler, Vec2};
use picomis_sim::scenes::{self, BUILTINS, HostScene};

/// Film sizes: the firmware's boards (64x48, 160x120), the Veach scene's own, a 1-pixel film
/// and sizes that do not divide into the tiles.
const FILMS: [(u32, u32); 6] = [(64, 48), (160, 120), (384, 256), (1, 1), (37, 23), (9, 200)];
/// Points per pixel besides its four corners.
const JITTERED: u32 = 4;

/// (rays, rays that hit, objects tested, objects in the scene per ray) of `scene` (built for
/// `film`), in the ray queries' arithmetic given.
fn check_scene(mut scene: HostScene, film: Film, arith: Arith) -> (u64, u64, u64, u64) {
    scene.enable_arith(arith).expect("every built-in scene can be represented in fixed point");
    let (w, h) = (film.width(), film.height());
    let mut rng = Sampler::new(5, w, h);
    let (mut rays, mut hits, mut tested) = (0u64, 0u64, 0u64);
    for y in 0..h {
        for x in 0..w {
            let corners = [Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0), Vec2::ONE];
            let jittered: Vec<Vec2> = (0..JITTERED).map(|_| rng.next_2d()).collect();
            for j in corners.into_iter().chain(jittered) {
                let uv = Vec2::new((x as f32 + j.x) / w as f32, (y as f32 + j.y) / h as f32);
                let (ray, t_near) = scene.camera().ray(uv);
                let full = scene.intersect(&ray, t_near, f32::INFINITY, None);
                let culled = scene.intersect_camera(&ray, t_near, x, y);
                assert_eq!(
                    format!("{culled:?}"),
                    format!("{full:?}"),
                    "pixel ({x}, {y}) of {w}x{h} at {j}: {ray:?}"
                );
                rays += 1;
                hits += u64::from(full.is_some());
            }
            tested += u64::from(scene.camera_candidates(x, y).count_ones()) * (4 + u64::from(JITTERED));
        }
    }
    (rays, hits, tested, rays * scene.objects().len() as u64)
}

#[test]
fn culled_camera_rays_hit_what_the_full_query_hits_on_every_builtin_scene() {
    check(Arith::F32, &FILMS);
}

/// The fixed-point queries cull the same objects (their hits are within about 1e-7 of the
/// scene's extent of the exact geometry, far inside the margin), on three of the films.
#[test]
fn culled_fixed_point_camera_rays_hit_what_the_full_query_hits_on_every_builtin_scene() {
    check(Arith::Fixed, &FILMS[..1]);
    check(Arith::Fixed, &FILMS[3..5]);
}

fn check(arith: Arith, films: &[(u32, u32)]) {
    for b in BUILTINS {
        let loaded = scenes::load(Some(b.name)).unwrap();
        let (mut rays, mut hits, mut tested, mut all) = (0, 0, 0, 0);
        for &(w, h) in films {
            let film = Film::new(w, h).unwrap();
            let (r, hi, t, a) = check_scene(loaded.build(film).unwrap(), film, arith);
            (rays, hits, tested, all) = (rays + r, hits + hi, tested + t, all + a);
        }
        println!(
            "{} ({arith:?}): {rays} camera rays, {:.1} % hit, {:.1} of {:.0} objects tested per ray",
            b.name,
            100.0 * hits as f64 / rays as f64,
            tested as f64 / rays as f64,
            all as f64 / rays as f64
        );
        assert!(hits * 2 > rays, "{}: {hits} of {rays} rays hit", b.name);
        if b.name == "veach_mis" {
            // 11 objects; the tiles leave about a third of them.
            assert!(tested * 2 < all, "{}: {tested} of {all} objects tested", b.name);
        }
    }
}
