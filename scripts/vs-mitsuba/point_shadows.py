"""Where picomis and Mitsuba 3 disagree on point_lights and glossy_lights: point lights' hard shadows, against an exact tracer.

Run by `scripts/vs-mitsuba.sh --point-shadows` (which sets up the venv and builds picomis-sim).

The claim (docs/vs-mitsuba.md, Reading): compare.py's agreement rule sees one block of point_lights,
(224, 160) (16x16 pixels of 480x360), where picomis's defaults lie about 9 standard errors above
Mitsuba's converged reference, and one of glossy_lights, (0, 16), about 6. Their z-scores run
along thin lines on the back walls: the edges of hard shadows cast from point lights (the balls'
on point_lights, the quad light's own on glossy_lights). To tell which renderer is right there,
each scene is reduced to what a closed computation can follow: the same geometry and camera with
only the point lights (the area lights' shapes stay, as occluders that emit nothing).
Then a pixel's value is the mean over its footprint of rho / pi * I * cos / d^2 * V, with nothing
sampled but the footprint, and this script computes it in f64 (numpy; its own ray-quad and
ray-sphere tests, no offsets: a shadow ray skips the surface it starts on, 128 x 128 stratified
positions per pixel). Pixels on the GGX ball are left out (not Lambertian).
Three estimates of the block and of its shadow-edge pixels (those the tracer finds partly shadowed):
1. the exact tracer;
2. picomis's defaults, 4 renders of 256 spp (mean ± standard error over the renders);
3. Mitsuba's `direct` integrator, independent sampler, on a crop of the block, `--passes` passes
   of 256 spp (it picks one of the two point lights per emitter sample, so it has light noise).
"""

import argparse
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import compare  # noqa: E402  (sets Mitsuba's variant)
from sphere_bias import SPP, mean_se, picomis_passes, read_pfm  # noqa: E402

mi = compare.mi

# (scene, its file in the repository, the block (x, y) at 480x360 where compare.py saw the difference)
SCENES = [("point_lights", "scenes/point_lights.json", (224, 160)),
          ("glossy_lights", "tests/scenes/glossy_lights.json", (0, 16))]
WIDTH, HEIGHT = 480, 360
SIZE = 16
FOOTPRINT = 128


def points_only(name, file, work):
    """The scene `file` (relative to the repository) without its area lights' emission, written as a file."""
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    with open(os.path.join(root, file), encoding="utf-8") as f:
        scene = json.load(f)
    for shape in scene["shapes"]:
        shape.pop("emitter", None)
    scene["name"] = f"{name}_points_only"
    path = os.path.join(work, f"{scene['name']}.json")
    with open(path, "w", encoding="utf-8") as f:
        json.dump(scene, f)
    return scene, path


class Exact:
    """Direct light of point lights on Lambertian surfaces, in f64."""

    def __init__(self, scene):
        cam = scene["camera"]
        self.origin = np.array(cam["origin"], dtype=np.float64)
        forward = np.array(cam["target"], dtype=np.float64) - self.origin
        self.forward = forward / np.linalg.norm(forward)
        right = np.cross(self.forward, np.array(cam["up"], dtype=np.float64))
        self.right = right / np.linalg.norm(right)
        self.up = np.cross(self.right, self.forward)
        assert cam.get("fov_axis", "y") == "y", cam
        self.tan_y = np.tan(np.radians(cam["fov_deg"]) / 2)
        self.tan_x = self.tan_y * WIDTH / HEIGHT
        materials = scene["materials"]
        self.shapes = []
        for s in scene["shapes"]:
            m = materials[s["material"]]
            albedo = np.array(m["albedo"], dtype=np.float64) if m["type"] == "lambertian" else None
            if s["type"] == "quad":
                p0, p1, _, p3 = (np.array(s[k], dtype=np.float64) for k in ("p0", "p1", "p2", "p3"))
                e1, e2 = p1 - p0, p3 - p0
                n = np.cross(e1, e2)
                n /= np.linalg.norm(n)
                if "normal" in s and np.dot(n, s["normal"]) < 0:
                    n = -n
                self.shapes.append(("quad", (p0, e1, e2, n), albedo))
            else:
                self.shapes.append(("sphere", (np.array(s["center"], dtype=np.float64), float(s["radius"])), albedo))
        self.lights = [(np.array(light["position"], dtype=np.float64), np.array(light["intensity"], dtype=np.float64))
                       for light in scene["lights"] if light["type"] == "point"]

    @staticmethod
    def distances(shape, o, d):
        """Distances along the rays (o, d) to the shape; inf where they miss (two for spheres)."""
        kind, g = shape
        with np.errstate(divide="ignore", invalid="ignore"):
            if kind == "quad":
                p0, e1, e2, n = g
                t = ((p0 - o) @ n) / (d @ n)
                q = o + t[:, None] * d - p0
                # Coordinates along the (parallelogram's) edges.
                g11, g12, g22 = e1 @ e1, e1 @ e2, e2 @ e2
                b1, b2 = q @ e1, q @ e2
                det = g11 * g22 - g12 * g12
                a, b = (b1 * g22 - b2 * g12) / det, (b2 * g11 - b1 * g12) / det
                inside = (a >= 0) & (a <= 1) & (b >= 0) & (b <= 1) & (t > 0)
                return (np.where(inside, t, np.inf),)
            c, r = g
            oc = o - c
            b = (oc * d).sum(1)
            disc = b * b - ((oc * oc).sum(1) - r * r)
            s = np.sqrt(np.where(disc >= 0, disc, np.nan))
            near, far = -b - s, -b + s
            return (np.where(near > 0, near, np.inf), np.where(far > 0, far, np.inf))

    def pixel(self, x, y):
        """The exact value of pixel (x, y) (RGB), and the fraction of its footprint in partial
        shadow of some light (0 or 1 where no shadow edge crosses it); None on non-Lambertian shapes."""
        g = (np.arange(FOOTPRINT) + 0.5) / FOOTPRINT
        fx, fy = np.meshgrid(g, g)
        px, py = x + fx.ravel(), y + fy.ravel()
        d = (self.forward[None] + ((2 * px / WIDTH - 1) * self.tan_x)[:, None] * self.right[None]
             - ((2 * py / HEIGHT - 1) * self.tan_y)[:, None] * self.up[None])
        d /= np.linalg.norm(d, axis=1)[:, None]
        o = np.broadcast_to(self.origin, d.shape)
        t = np.full(len(d), np.inf)
        hit = np.full(len(d), -1)
        for i, shape in enumerate(self.shapes):
            ti = np.fmin.reduce(self.distances(shape[:2], o, d))
            closer = ti < t
            t[closer], hit[closer] = ti[closer], i
        if (hit < 0).any() or any(self.shapes[i][2] is None for i in np.unique(hit)):
            return None
        p = o + t[:, None] * d
        n = np.zeros_like(p)
        albedo = np.zeros_like(p)
        for i, (kind, g_, a) in enumerate(self.shapes):
            m = hit == i
            n[m] = g_[3] if kind == "quad" else (p[m] - g_[0]) / g_[1]
            albedo[m] = a
        value = np.zeros(3)
        shadowed = []
        for position, intensity in self.lights:
            v = position - p
            dist = np.linalg.norm(v, axis=1)
            w = v / dist[:, None]
            blocked = np.zeros(len(p), dtype=bool)
            for i, shape in enumerate(self.shapes):
                for ti in self.distances(shape[:2], p, w):
                    blocked |= (hit != i) & (ti < dist)
            cos = (n * w).sum(1)
            lit = (~blocked) & (cos > 0)
            value += (albedo * (intensity / np.pi)[None] * np.where(lit, cos / dist**2, 0)[:, None]).mean(0)
            shadowed.append(blocked[cos > 0].mean() if (cos > 0).any() else 0.0)
        edge = any(0 < s < 1 for s in shadowed)
        return value, edge


def measure(args, name, file, block):
    """The report's rows for one scene: its block's pixels, exact, picomis's and Mitsuba's."""
    x0, y0 = block
    scene, path = points_only(name, file, args.work)
    exact = Exact(scene)
    truth = np.full((SIZE, SIZE, 3), np.nan)
    edge = np.zeros((SIZE, SIZE), dtype=bool)
    for j in range(SIZE):
        for i in range(SIZE):
            got = exact.pixel(x0 + i, y0 + j)
            if got is not None:
                truth[j, i], edge[j, i] = got
    keep = ~np.isnan(truth[:, :, 0])

    size = ["--width", str(WIDTH), "--height", str(HEIGHT)]
    picomis = [img[y0:y0 + SIZE, x0:x0 + SIZE]
               for img in picomis_passes(args.picomis, path, size, 4, os.path.join(args.work, "point_shadows.pfm"))]

    exported = compare.export_scene(args.picomis, f"{name}_points_only", path, "file", WIDTH, HEIGHT, args.work)
    cropped = compare.crop_xml(exported, x0, y0, SIZE, SIZE,
                               os.path.join(args.work, f"{name}_points_only_block.xml"))
    s = compare.load_mitsuba(exported, "independent", SPP, cropped)
    mitsuba = [np.array(mi.render(s, spp=SPP, seed=7_000_000 + k), dtype=np.float64)[:, :, :3]
               for k in range(args.passes)]

    rows = []
    for label, mask in [("all Lambertian", keep), ("shadow edges", edge & keep), ("no shadow edge", keep & ~edge)]:
        if not mask.any():
            continue
        t = truth[mask].mean()
        p, p_se = mean_se([img[mask].mean() for img in picomis])
        m, m_se = mean_se([img[mask].mean() for img in mitsuba])
        rows.append(
            f"| {name} ({x0}, {y0}) | {label} ({int(mask.sum())}) | {t:.6f} | {p:.6f} ± {p_se:.1g} | "
            f"{p / t - 1:+.1e} | {(p - t) / p_se:+.1f} | {m:.6f} ± {m_se:.1g} | {m / t - 1:+.1e} | "
            f"{(m - t) / m_se:+.1f} |")
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--picomis", required=True, help="picomis-sim binary")
    ap.add_argument("--work", required=True, help="scratch folder")
    ap.add_argument("--passes", type=int, default=256, help="Mitsuba passes of 256 spp on each block")
    ap.add_argument("--out", help="also write the report to this markdown file")
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)

    lines = [
        "# Point lights' hard shadows in Mitsuba 3 and picomis against an exact tracer",
        "",
        f"Mitsuba {mi.__version__} `llvm_ad_rgb`. Written by `scripts/vs-mitsuba.sh --point-shadows` "
        "(`scripts/vs-mitsuba/point_shadows.py`, whose docstring has the method). Each scene with its "
        f"point lights only, {WIDTH}x{HEIGHT}; the {SIZE}x{SIZE} block where compare.py saw the renderers "
        "differ; its Lambertian pixels, split into those a shadow edge crosses (partly shadowed from some "
        "light, by the exact tracer) and the others.",
        "",
        "| scene (block) | pixels | exact (f64) | picomis, defaults | relative | z | Mitsuba, independent "
        "| relative | z |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name, file, block in SCENES:
        lines += measure(args, name, file, block)
    lines += [
        "",
        f"picomis: 4 renders of {SPP} spp; Mitsuba: {args.passes} passes of {SPP} spp on a crop of the block; "
        "mean ± standard error over them; z against the exact value.",
    ]
    compare.report("\n".join(lines), args.out)


if __name__ == "__main__":
    sys.exit(main())
