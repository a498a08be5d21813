"""Where picomis and Mitsuba 3 disagree on Veach: Mitsuba's sampling of small sphere lights, against closed forms.

Run by `scripts/vs-mitsuba.sh --sphere-bias` (which sets up the venv and builds picomis-sim).

The claim (docs/vs-mitsuba.md, Reading): compare.py's agreement rule fails picomis's defaults on
Veach at the block (48, 208) (16x16 pixels, 384x256), on the alpha = 0.1 plate, where Mitsuba's
converged image is about 1e-3 brighter than picomis's. Two measurements:
1. A Lambertian plane (albedo 0.5) under a sphere light of radius r at height d above the origin,
   seen from far away through a 4x4 film of 0.0005 degrees: the exact outgoing radiance there is
   rho L r^2 / d^2 (the sphere wholly above the horizon). Mitsuba's `direct` integrator with
   emitter samples only (its sphere light sampling) and picomis's lecture preset (cone sampling
   and BSDF samples, power heuristic), each in passes of 256 spp (so that no f32 running sum
   drifts: picomis's PixelSum is plain up to 256 samples, and so is each pass of Mitsuba's film);
   mean and standard error over the passes.
2. The Veach block itself: Mitsuba's independent sampler on a crop of the block, `--passes` passes
   of 256 spp, against picomis's defaults, four full renders of 256 spp.
"""

import argparse
import json
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import compare  # noqa: E402  (sets Mitsuba's variant)

mi = compare.mi

RHO, RADIANCE = 0.5, 901.803
# (r, d): Veach's smallest light (r = 0.0333) at about its distance from the plates, and larger ones.
SPHERES = [(0.03333, 5.0), (0.1, 5.0), (0.3, 5.0), (0.9, 5.0), (0.03333, 2.0)]
BLOCK = (48, 208)
SPP = 256


def read_pfm(path):
    with open(path, "rb") as f:
        f.readline()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(h, w, 3)[::-1].astype(np.float64)


def picomis_sphere_scene(r, d):
    return {
        "format": "picomis-scene/1",
        "name": "sphere_over_plane",
        "film": {"width": 4, "height": 4, "pixel_filter": "box"},
        "camera": {"type": "perspective", "origin": [20, 20, 0], "target": [0, 0, 0], "up": [0, 1, 0],
                   "fov_deg": 0.0005, "fov_axis": "y"},
        "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 1, "mis": "power"},
        "materials": {"plane": {"type": "lambertian", "albedo": [RHO] * 3},
                      "black": {"type": "lambertian", "albedo": [0, 0, 0]}},
        "shapes": [
            {"type": "quad", "name": "plane", "p0": [-50, 0, -50], "p1": [-50, 0, 50], "p2": [50, 0, 50],
             "p3": [50, 0, -50], "material": "plane", "normal": [0, 1, 0]},
            {"type": "sphere", "name": "light", "center": [0, d, 0], "radius": r, "material": "black",
             "emitter": {"type": "area", "radiance": [RADIANCE] * 3}},
        ],
    }


def mitsuba_sphere_scene(r, d):
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0},
        "sensor": {"type": "perspective", "fov": 0.0005,
                   "to_world": mi.ScalarTransform4f().look_at(origin=[20, 20, 0], target=[0, 0, 0], up=[0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": 4, "height": 4, "rfilter": {"type": "box"},
                            "pixel_format": "rgb"},
                   "sampler": {"type": "independent", "sample_count": SPP}},
        "plane": {"type": "rectangle", "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90).scale(50),
                  "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [RHO] * 3}}},
        "light": {"type": "sphere", "center": [0, d, 0], "radius": r,
                  "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [RADIANCE] * 3}}},
    })


def mean_se(values):
    v = np.asarray(values, dtype=np.float64)
    return v.mean(), v.std(ddof=1) / np.sqrt(len(v))


def picomis_passes(picomis, scene, flags, passes, out):
    values = []
    for k in range(passes):
        cmd = [picomis, "render", scene, "--spp", str(SPP), "--seed", str(100 + k), "--out", out] + flags
        subprocess.run(cmd, check=True, capture_output=True)
        values.append(read_pfm(out))
    return values


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--picomis", required=True, help="picomis-sim binary")
    ap.add_argument("--work", required=True, help="scratch folder")
    ap.add_argument("--passes", type=int, default=8192, help="Mitsuba passes of 256 spp on the Veach block")
    ap.add_argument("--out", help="also write the report to this markdown file")
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)

    lines = [
        "# Sphere lights in Mitsuba 3 and picomis against closed forms",
        "",
        f"Mitsuba {mi.__version__} `llvm_ad_rgb`; every estimate in passes of {SPP} spp (no f32 running sum "
        "over more samples); mean ± standard error over the passes. Written by `scripts/vs-mitsuba.sh "
        "--sphere-bias` (`scripts/vs-mitsuba/sphere_bias.py`, whose docstring has the method).",
        "",
        "## A Lambertian plane under a sphere light: rho L r² / d² below the centre",
        "",
        "| r | d | sin α | exact | Mitsuba, emitter samples | relative | picomis, lecture preset | relative |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r, d in SPHERES:
        exact = RHO * RADIANCE * r * r / (d * d)
        scene = mitsuba_sphere_scene(r, d)
        m, m_se = mean_se([np.array(mi.render(scene, spp=SPP, seed=k), dtype=np.float64)[:, :, :3].mean()
                           for k in range(64)])
        path = os.path.join(args.work, f"sphere_{r}_{d}.json")
        with open(path, "w", encoding="utf-8") as f:
            json.dump(picomis_sphere_scene(r, d), f)
        p, p_se = mean_se([img.mean() for img in picomis_passes(
            args.picomis, path, ["--preset", "lecture"], 16, os.path.join(args.work, "sphere.pfm"))])
        lines.append(f"| {r} | {d} | {r / d:.4f} | {exact:.6f} | {m:.6f} ± {m_se:.1g} | {m / exact - 1:+.1e} "
                     f"| {p:.6f} ± {p_se:.1g} | {p / exact - 1:+.1e} |")

    scene = compare.export_scene(args.picomis, "veach_mis", "veach_mis", "built-in", 384, 256, args.work)
    cropped = compare.crop_xml(scene, *BLOCK, 16, 16, os.path.join(args.work, "veach_block.xml"))
    s = compare.load_mitsuba(scene, "independent", SPP, cropped)
    m, m_se = mean_se([np.array(mi.render(s, spp=SPP, seed=5_000_000 + k), dtype=np.float64)[:, :, :3].mean()
                       for k in range(args.passes)])
    x, y = BLOCK
    p, p_se = mean_se([img[y:y + 16, x:x + 16].mean() for img in picomis_passes(
        args.picomis, "veach_mis", [], 4, os.path.join(args.work, "veach.pfm"))])
    z = (p - m) / np.hypot(p_se, m_se)
    lines += [
        "",
        f"## Veach, the block ({x}, {y}) (alpha = 0.1 plate)",
        "",
        "| renderer | mean | relative to Mitsuba |",
        "|---|---:|---:|",
        f"| Mitsuba, independent sampler, {args.passes} x {SPP} spp | {m:.6f} ± {m_se:.1g} | |",
        f"| picomis, defaults, 4 x {SPP} spp | {p:.6f} ± {p_se:.1g} | {p / m - 1:+.1e} (z {z:+.1f}) |",
    ]
    compare.report("\n".join(lines), args.out)


if __name__ == "__main__":
    sys.exit(main())
