"""picomis against Mitsuba 3 on every built-in scene, at equal spp: relative MSE, render time, efficiency.

Run by scripts/vs-mitsuba.sh (which sets up the venv and builds picomis-sim); see there.

Per scene (`picomis-sim scenes`; `--scenes` picks some, Veach first):
- The Mitsuba scene is `picomis-sim export NAME`, with its sampler and film size made parameters.
- The image size is the scene's own, scaled by an integer factor to at least `--min-pixels`
  (default 384x256, the Veach scene's), so that render times measure throughput, not start-up.
- Every renderer uses the exported `direct` integrator's settings: its light and BSDF sample counts
  and the power heuristic (beta 2), the only heuristic Mitsuba's `direct` integrator has; picomis
  gets them as flags, so a scene's own default method does not matter.
- The exported scene must be the same scene: Mitsuba's converged image and picomis' converged
  image (its first configuration) must agree, per RGB channel, on 16x16-pixel blocks outside the
  emitters: z = (block mean difference) / (its standard error from the spread of the block means
  over independent passes), |z| < 3 in at least 97 % of the blocks and the whole image within
  |z| < 4. Where the blocks disagree, the difference is still negligible for this comparison if
  it is systematic at a level far below the errors compared: the relative MSE between the two
  means, less what their noise explains, under 5 % of the smallest error in the scene's table
  (the verdict says "close"). Otherwise the verdict is "no", in bold.
- The reference is independent of picomis: Mitsuba's converged image (`--ref-passes` passes of
  `--ref-spp` spp with `--ref-sampler`, independent seeds; more passes for the scenes of
  REFERENCE_PASSES; for stress with the tiny light as a point light, see REFERENCE_FIXES), cached under
  the work folder. Its own
  noise is the variance of its mean over the passes; that noise adds its relative MSE to every
  row's, and the table states it and its share of the smallest error compared. (Veach's
  committed ~37,000-spp reference, independent sampler, is not used here: its noise, about
  4e-5, is a fifth of the smallest error measured on it.)
- The error is the relative MSE, mean of (I - R)^2 / (R^2 + 0.01) over pixels and RGB channels,
  leaving out the pixels that see an emitter (found by a Mitsuba path tracer of depth 1, which
  renders only the emission seen directly) and their 8 neighbours.
- Rounds are interleaved: in each round, for each scene, every picomis configuration renders, then
  every Mitsuba sampler.
- Only render time counts: Mitsuba renders each (scene, sampler) once to compile its kernels
  (JIT), then the timed renders run in the same process; picomis' time is the render time it
  prints (scene loading and file writing excluded).
- Efficiency is 1 / (relative MSE x seconds); per row its range over rounds, the ratio of medians.
"""

import argparse
import hashlib
import math
import os
import re
import statistics
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

import drjit as dr
import mitsuba as mi
import numpy as np

mi.set_variant("llvm_ad_rgb")

# (sampler, spp) at --spp 64; orthogonal needs the square of a prime (121 = 11^2).
MITSUBA = [("independent", 64), ("stratified", 64), ("multijitter", 64), ("ldsampler", 64), ("orthogonal", 121)]

# NAME=FLAGS: the defaults; the defaults with light selection by contribution (not the default:
# it costs O(lights) per shading point, which does not pay on every scene); that with light
# samples also from a glossy receiver's lobe (`--lobe-mixing on`: only near-mirrors under larger
# lights gain); the defaults with the control variate (closed-form unoccluded light at Lambertian receivers, the occluded rest sampled
# with the same MIS: README "Beyond the lecture"; not the default either, it pays only where
# occlusion is rare).
PICOMIS_CONFIGS = ["picomis=", "picomis, lights by contribution=--light-selection contribution",
                   "picomis, by contribution + lobe=--light-selection contribution --lobe-mixing on",
                   "picomis, control variate=--control-variate on"]


BLOCK = 16

# Mitsuba 3.9's tiny spheres are biased: its cone sampling takes 1 - cos(theta_max) in float32,
# which for stress' r = 0.001 light makes its image of the floor about 11 % too bright (up to 50 %
# in places; picomis gives the same image at r = 0.001 and r = 0.01). Its references of these
# scenes therefore replace the named sphere lights by point lights of intensity L pi r^2: a
# Lambertian sphere wholly above a receiver's horizon gives it exactly the irradiance of that
# point light, and the mask leaves out the pixels that see the sphere. Mitsuba's timed renders
# keep the scene as it is. (An enlarged sphere, the same power at 10 times the radius, left
# Mitsuba's floor 0.04 % too bright, its float32 rounding; at 30 times, the sphere's shadow of the
# quad light, 0.5 % on a band of the floor, showed.)
REFERENCE_FIXES = {"stress": ["tiny_light"]}

# Reference passes per scene where --ref-passes' default is too few: on lambert_sphere (nothing
# occludes its light) the control variate's error at 64 spp is below a 16-pass reference's own
# noise. At 64 passes the noise is still most of that row's measured error (the table says how
# much), so its efficiency there is a lower bound.
# On Veach the best picomis configuration's error (about 1.9e-4) is five times the noise of the
# committed ~37,000-spp reference (independent sampler; host-sim/tests/data); 128 passes of 256
# spp with REFERENCE_SAMPLER bring the reference's share under a few per cent.
# On stress, lobe mixing with selection by contribution (about 2.4e-5) put a 16-pass reference's
# noise at 13 % of the best error; 64 passes bring it to about 3 %.
REFERENCE_PASSES = {"lambert_sphere": 64, "stress": 64, "veach_mis": 128}

# The references' sampler: multijitter, not ldsampler. Mitsuba 3.9's ldsampler converges to a
# biased image at the soft edges of glossy reflections: on Veach, the left edge of the r = 0.9
# light's reflection in the alpha = 0.005 plate (x 266-275, y 112-115 at 384x256), 8 passes of
# 256 spp with new seeds give 0.158 / 0.727 at x = 271 / 272 where independent, stratified and
# multijitter give 0.134-0.138 / 0.745-0.749 (and picomis 0.131-0.136 / 0.744-0.750); that edge
# alone made Veach's same-scene check fail. Multijitter agrees with the independent sampler there
# and converges almost as fast as ldsampler.
REFERENCE_SAMPLER = "multijitter"


@dataclass
class Scene:
    name: str
    width: int
    height: int
    xml: str
    ref_xml: str  # the scene for Mitsuba's reference (REFERENCE_FIXES)
    base_flags: list  # picomis flags for the exported integrator's settings
    keep: np.ndarray = None  # (h, w, 3) bool: pixels that see no emitter
    reference: np.ndarray = None
    reference_label: str = ""
    reference_noise: float = None  # its relative MSE against the truth (estimated)
    agreement: dict = None
    rows: dict = field(default_factory=dict)  # row name -> (spp, [(relMSE, seconds)])


def parse_config(text):
    name, _, flags = text.partition("=")
    return name, flags.split()


def load_exr(path):
    return np.array(mi.Bitmap(str(path)), dtype=np.float64)[:, :, :3]


def rel_mse(img, ref, keep):
    e = (img - ref) ** 2 / (ref**2 + 0.01)
    return float(e[keep].mean())


def digest(*parts):
    h = hashlib.sha256()
    for p in parts:
        h.update(p if isinstance(p, bytes) else str(p).encode())
    return h.hexdigest()[:16]


def builtin_scenes(picomis):
    """(name, width, height) of every built-in scene, Veach first."""
    out = subprocess.run([picomis, "scenes"], capture_output=True, text=True, check=True).stdout
    found = [(m[1], int(m[2]), int(m[3])) for m in re.finditer(r"^(\S+)\s+(\d+)x(\d+)", out, re.M)]
    return sorted(found, key=lambda s: s[0] != "veach_mis")


def scaled(width, height, min_pixels):
    k = 1
    while (k * width) * (k * height) < min_pixels:
        k += 1
    return k * width, k * height


def export_scene(picomis, name, width, height, work):
    """Exports NAME to Mitsuba XML with $sampler, $resx and $resy parameters; returns the Scene."""
    raw = os.path.join(work, f"{name}.export.xml")
    subprocess.run([picomis, "export", name, "--mitsuba", raw], capture_output=True, check=True)
    tree = ET.parse(raw)
    root = tree.getroot()
    for i, (k, v) in enumerate([("sampler", "independent"), ("resx", width), ("resy", height)]):
        root.insert(i, ET.Element("default", name=k, value=str(v)))
    root.find("sensor/sampler").set("type", "$sampler")
    film = root.find("sensor/film")
    film.find("integer[@name='width']").set("value", "$resx")
    film.find("integer[@name='height']").set("value", "$resy")
    integ = root.find("integrator")
    assert integ.get("type") == "direct", integ.get("type")
    counts = {e.get("name"): e.get("value") for e in integ.findall("integer")}
    xml = os.path.join(work, f"{name}.xml")
    tree.write(xml, encoding="utf-8", xml_declaration=True)
    ref_xml = xml
    if name in REFERENCE_FIXES:
        for shape in [s for s in root.findall("shape") if s.get("id") in REFERENCE_FIXES[name]]:
            assert shape.get("type") == "sphere", shape.get("id")
            r = float(shape.find("float[@name='radius']").get("value"))
            radiance = [float(v) for v in shape.find("emitter/rgb[@name='radiance']").get("value").split(",")]
            point = ET.Element("emitter", type="point", id=shape.get("id"))
            position = ET.SubElement(point, "point", name="position")
            for axis in "xyz":
                position.set(axis, shape.find("point[@name='center']").get(axis))
            intensity = ", ".join(repr(v * math.pi * r * r) for v in radiance)
            ET.SubElement(point, "rgb", name="intensity", value=intensity)
            root.remove(shape)
            root.append(point)
        ref_xml = os.path.join(work, f"{name}.reference.xml")
        tree.write(ref_xml, encoding="utf-8", xml_declaration=True)
    flags = ["--mis", "power", "--beta", "2", "--light-samples", counts.get("emitter_samples", "1"),
             "--bsdf-samples", counts.get("bsdf_samples", "1"), "--width", str(width), "--height", str(height)]
    return Scene(name, width, height, xml, ref_xml, flags)


def load_mitsuba(scene, sampler, spp, xml=None):
    return mi.load_file(xml or scene.xml, sampler=sampler, spp=spp, resx=scene.width, resy=scene.height)


def emitter_mask(scene, xml):
    """True where a pixel sees no emitter: a depth-1 path tracer renders only visible emission, and
    the mask grows by one pixel, so that pixels where an emitter covers too little to be found at
    256 spp (which then turn up as a rare emitter sample, the largest error in the image) stay out."""
    s = load_mitsuba(scene, "stratified", 256, xml)
    emitted = np.array(mi.render(s, spp=256, integrator=mi.load_dict({"type": "path", "max_depth": 1})))
    seen = np.pad(emitted[:, :, :3].max(axis=2) > 0.0, 1)
    h, w = scene.height, scene.width
    near = np.zeros((h, w), dtype=bool)
    for dy in range(3):
        for dx in range(3):
            near |= seen[dy : dy + h, dx : dx + w]
    return np.broadcast_to(~near[:, :, None], (h, w, 3))


def cached_stack(path, make):
    """An (n, h, w, 3) float32 stack of independent images, from `path` or made and saved there."""
    if os.path.exists(path):
        return np.load(path)["stack"]
    stack = make()
    np.savez(path, stack=stack)
    return stack


def mitsuba_stack(scene, sampler, spp, passes, work):
    key = digest(open(scene.ref_xml, "rb").read(), mi.__version__, sampler, spp, passes)
    path = os.path.join(work, f"{scene.name}.mitsuba.{sampler}.{passes}x{spp}.{key}.npz")

    def make():
        s = load_mitsuba(scene, sampler, spp, scene.ref_xml)
        imgs = []
        for k in range(passes):
            t0 = time.perf_counter()
            imgs.append(np.array(mi.render(s, spp=spp, seed=1_000_000 + k), dtype=np.float32)[:, :, :3])
            print(f"  {scene.name}: Mitsuba {sampler} pass {k + 1}/{passes}, {spp} spp, "
                  f"{time.perf_counter() - t0:.1f} s", flush=True)
        return np.stack(imgs)

    return cached_stack(path, make)


def picomis_render(picomis, scene, flags, spp, seed, out):
    """Renders with picomis; returns (image, render seconds as picomis prints them)."""
    cmd = [picomis, "render", scene.name, "--spp", str(spp), "--seed", str(seed), "--out", out]
    p = subprocess.run(cmd + scene.base_flags + flags, capture_output=True, text=True, check=True)
    return load_exr(out), float(re.search(r", ([0-9.]+) s, ", p.stderr).group(1))


def picomis_stack(picomis, scene, flags, spp, seeds, work):
    key = digest(open(picomis, "rb").read(), scene.base_flags, flags, spp, seeds)
    path = os.path.join(work, f"{scene.name}.picomis.{seeds}x{spp}.{key}.npz")

    def make():
        out = os.path.join(work, f"{scene.name}.converged.exr")
        imgs = [picomis_render(picomis, scene, flags, spp, 1_000_000 + k, out)[0] for k in range(seeds)]
        return np.stack(imgs).astype(np.float32)

    return cached_stack(path, make)


def block_means(stack, keep):
    """(n, by, bx, 3) means of each pass over the kept pixels of each 16x16 block, and the mask of
    the blocks that are at least half kept."""
    n, h, w, _ = stack.shape
    by, bx = h // BLOCK, w // BLOCK
    k = keep[: by * BLOCK, : bx * BLOCK, 0].reshape(by, BLOCK, bx, BLOCK).astype(np.float64)
    s = stack[:, : by * BLOCK, : bx * BLOCK].reshape(n, by, BLOCK, bx, BLOCK, 3).astype(np.float64)
    count = k.sum(axis=(1, 3))
    sums = (s * k[None, :, :, :, :, None]).sum(axis=(2, 4))
    return sums / np.maximum(count, 1)[None, :, :, None], count >= BLOCK * BLOCK / 2


def agreement(a, b, keep):
    """Block z-scores between two stacks of independent passes (module docs), per channel."""
    ma, ok = block_means(a, keep)
    mb, _ = block_means(b, keep)
    diff = ma.mean(axis=0) - mb.mean(axis=0)
    se = np.sqrt(ma.var(axis=0, ddof=1) / len(a) + mb.var(axis=0, ddof=1) / len(b))
    z = diff[ok] / np.maximum(se[ok], 1e-30)  # (blocks, 3)
    # The whole image: the mean of the usable blocks, per pass.
    wa, wb = ma[:, ok].mean(axis=1), mb[:, ok].mean(axis=1)  # (n, 3)
    whole = wa.mean(axis=0) - wb.mean(axis=0)
    whole_z = whole / np.sqrt(wa.var(axis=0, ddof=1) / len(a) + wb.var(axis=0, ddof=1) / len(b))
    rel = np.abs(diff[ok]) / np.maximum(np.abs(mb.mean(axis=0)[ok]), 1e-3)
    within3 = (np.abs(z) < 3).mean(axis=0)
    # The systematic difference as a relative MSE: that of the two means, less what their noise
    # explains. It is the floor that a difference between the two renderers' models (not their
    # noise) adds to picomis' error against a Mitsuba reference.
    pa, pb = a.astype(np.float64), b.astype(np.float64)
    ref = pb.mean(axis=0)
    noise = pa.var(axis=0, ddof=1) / len(a) + pb.var(axis=0, ddof=1) / len(b)
    bias = ((pa.mean(axis=0) - ref) ** 2 - noise) / (ref**2 + 0.01)
    return dict(
        bias=float(bias[keep].mean()),
        blocks=int(ok.sum()),
        within3=within3,
        max_z=np.abs(z).max(axis=0),
        whole_rel=whole / wb.mean(axis=0),
        whole_z=whole_z,
        mean_rel=rel.mean(axis=0),
        agrees=bool(ok.sum() >= 50 and (within3 >= 0.97).all() and (np.abs(whole_z) < 4).all()),
    )


def describe_agreement(a, label):
    ch = lambda v, f: "/".join(format(x, f) for x in v)  # noqa: E731
    return (f"{label}: {a['blocks']} 16x16 blocks outside the emitters, |z| < 3 in "
            f"{ch(100 * a['within3'], '.1f')} % (R/G/B), max |z| {ch(a['max_z'], '.1f')}, whole image "
            f"{ch(100 * a['whole_rel'], '+.2f')} % (z {ch(a['whole_z'], '+.1f')}), mean |relative "
            f"difference| per block {ch(100 * a['mean_rel'], '.2f')} %, systematic difference (relative "
            f"MSE of the means less their noise) {a['bias']:.2g} -> "
            f"{'agree' if a['agrees'] else '**the blocks disagree**'}")


def same_scene(scene, smallest):
    """The verdict: the blocks agree, or their difference is negligible against the errors compared."""
    a = scene.agreement
    if a["agrees"]:
        return "yes"
    share = f"{100 * a['bias'] / smallest:.1f} % of the smallest error"
    return f"close: systematic {a['bias']:.2g} ({share})" if a["bias"] < 0.05 * smallest else f"**no** ({share})"


def prepare(args, configs, name, width, height):
    """Exports, masks, checks and references one scene (the untimed part)."""
    scene = export_scene(args.picomis, name, *scaled(width, height, args.min_pixels), args.work)
    print(f"{name}: {scene.width}x{scene.height}, {scene.xml}", flush=True)
    scene.keep = emitter_mask(scene, scene.xml) & emitter_mask(scene, scene.ref_xml)
    print(f"  {(~scene.keep[:, :, 0]).sum()} of {scene.width * scene.height} pixels see an emitter "
          f"and are left out", flush=True)
    passes = max(args.ref_passes, REFERENCE_PASSES.get(name, 0))
    converged = mitsuba_stack(scene, args.ref_sampler, args.ref_spp, passes, args.work)
    ours = picomis_stack(args.picomis, scene, configs[0][1], args.check_spp, args.check_seeds, args.work)
    scene.agreement = agreement(ours, converged, scene.keep)
    print("  " + describe_agreement(scene.agreement, "picomis vs Mitsuba, converged"), flush=True)

    scene.reference = converged.astype(np.float64).mean(axis=0)
    var = converged.astype(np.float64).var(axis=0, ddof=1) / len(converged)
    scene.reference_noise = float((var / (scene.reference**2 + 0.01))[scene.keep].mean())
    scene.reference_label = (f"Mitsuba's converged image ({passes} x {args.ref_spp} spp, "
                             f"{args.ref_sampler}"
                             f"{', with the sphere lights of REFERENCE_FIXES as point lights' if name in REFERENCE_FIXES else ''})")
    return scene


def run_rounds(args, configs, scenes):
    """Interleaved rounds; fills scene.rows; returns the load average at the start of each round."""
    mitsuba = {}
    for scene in scenes:
        for name, spp in MITSUBA:
            s = load_mitsuba(scene, name, spp)
            dr.eval(mi.render(s, spp=spp, seed=1000))  # compile (JIT) once, untimed
            mitsuba[scene.name, name] = (s, spp)
        for name, _ in configs:
            scene.rows[name] = (args.spp, [])
        for name, spp in MITSUBA:
            scene.rows[f"Mitsuba 3, {name}"] = (spp, [])
    loads = []
    out = os.path.join(args.work, "round.exr")
    for r in range(args.rounds):
        loads.append(os.getloadavg()[0])
        for scene in scenes:
            for name, flags in configs:
                img, secs = picomis_render(args.picomis, scene, flags, args.spp, r, out)
                scene.rows[name][1].append((rel_mse(img, scene.reference, scene.keep), secs))
                print(f"round {r}: {scene.name}: {name}: relMSE {scene.rows[name][1][-1][0]:.3g}, "
                      f"{secs:.3f} s", flush=True)
            for name, spp in MITSUBA:
                s, _ = mitsuba[scene.name, name]
                t0 = time.perf_counter()
                img = mi.render(s, spp=spp, seed=r)
                dr.eval(img)
                dr.sync_thread()
                secs = time.perf_counter() - t0
                key = f"Mitsuba 3, {name}"
                err = rel_mse(np.array(img, dtype=np.float64)[:, :, :3], scene.reference, scene.keep)
                scene.rows[key][1].append((err, secs))
                print(f"round {r}: {scene.name}: {key}: relMSE {err:.3g}, {secs:.3f} s", flush=True)
    return loads


def efficiencies(runs):
    return [1.0 / (e * s) for e, s in runs]


def best(scene, mitsuba):
    """(row name, median efficiency) of the best picomis row, or of the best Mitsuba row."""
    rows = [(k, statistics.median(efficiencies(v))) for k, (_, v) in scene.rows.items()
            if k.startswith("Mitsuba") == mitsuba]
    return max(rows, key=lambda kv: kv[1])


def smallest_error(scene):
    return min(statistics.mean(e for e, _ in v) for _, v in scene.rows.values())


def scene_table(scene):
    _, best_mitsuba = best(scene, mitsuba=True)
    smallest = smallest_error(scene)
    lines = [
        f"## {scene.name} ({scene.width}x{scene.height})",
        "",
        f"Reference: {scene.reference_label}; its own noise adds about {scene.reference_noise:.2e} to "
        f"every relative MSE ({100 * scene.reference_noise / smallest:.1f} % of the smallest below"
        f"{'; **too noisy**: raise --ref-passes or --ref-spp' if scene.reference_noise > 0.1 * smallest else ''}).",
        "",
        describe_agreement(scene.agreement, "Same scene? picomis' and Mitsuba's converged images")
        + f". Verdict: {same_scene(scene, smallest)}.",
        "",
        "| renderer, sampler | spp | relative MSE | render s | efficiency 1/(relMSE x s) | vs Mitsuba's best |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for k, (spp, v) in scene.rows.items():
        errs, secs, effs = [e for e, _ in v], [s for _, s in v], efficiencies(v)
        lines.append(
            f"| {k} | {spp} | {statistics.mean(errs):.3g} | {min(secs):.3f}-{max(secs):.3f} | "
            f"{min(effs):,.0f}-{max(effs):,.0f} | {statistics.median(effs) / best_mitsuba:.2f}x |"
        )
    return "\n".join(lines)


def summary_table(scenes):
    lines = [
        "| scene | picomis' best | efficiency | Mitsuba's best | efficiency | ratio | same scene |",
        "|---|---|---:|---|---:|---:|---|",
    ]
    for scene in scenes:
        (pk, pe), (mk, me) = best(scene, mitsuba=False), best(scene, mitsuba=True)
        smallest = smallest_error(scene)
        ratio = pe / me
        lines.append(f"| {scene.name} | {pk} | {pe:,.0f} | {mk.removeprefix('Mitsuba 3, ')} | {me:,.0f} | "
                     f"{'**' if ratio < 1 else ''}{ratio:.2f}x{'**' if ratio < 1 else ''} | "
                     f"{same_scene(scene, smallest)} |")
    return "\n".join(lines)


def cpu_name():
    try:
        with open("/proc/cpuinfo") as f:
            return next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        return "unknown"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--picomis", required=True, help="picomis-sim binary")
    ap.add_argument("--out", required=True, help="markdown file to write")
    ap.add_argument("--work", required=True, help="scratch and cache folder")
    ap.add_argument("--scenes", default="", help="comma-separated built-in scenes (default: all, Veach first)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--spp", type=int, default=64, help="picomis' spp (Mitsuba's are in MITSUBA)")
    ap.add_argument("--min-pixels", type=int, default=384 * 256,
                    help="scale each scene's size by an integer factor to at least this many pixels")
    ap.add_argument("--picomis-config", action="append", metavar="NAME=FLAGS",
                    help="a picomis configuration (repeatable; replaces the list: "
                         + "; ".join(PICOMIS_CONFIGS) + "). The first also renders the converged image "
                         "of the same-scene check")
    ap.add_argument("--add-picomis-config", action="append", default=[], metavar="NAME=FLAGS",
                    help="a picomis configuration to add to the list (repeatable)")
    ap.add_argument("--ref-sampler", default=REFERENCE_SAMPLER, help="Mitsuba sampler of the references")
    ap.add_argument("--ref-spp", type=int, default=256, help="spp per reference pass")
    ap.add_argument("--ref-passes", type=int, default=16, help="independent passes per reference")
    ap.add_argument("--check-spp", type=int, default=64, help="spp per picomis pass of the same-scene check")
    ap.add_argument("--check-seeds", type=int, default=16, help="picomis passes of the same-scene check")
    args = ap.parse_args()

    configs = [parse_config(c) for c in (args.picomis_config or PICOMIS_CONFIGS) + args.add_picomis_config]
    available = builtin_scenes(args.picomis)
    wanted = [s for s in args.scenes.split(",") if s]
    unknown = set(wanted) - {n for n, _, _ in available}
    if unknown:
        ap.error(f"unknown scenes: {', '.join(sorted(unknown))} (see `picomis-sim scenes`)")
    os.makedirs(args.work, exist_ok=True)

    load_before = os.getloadavg()[0]
    t0 = time.perf_counter()
    scenes = [prepare(args, configs, *s) for s in available if not wanted or s[0] in wanted]
    loads = run_rounds(args, configs, scenes)
    load_after = os.getloadavg()[0]

    header = (
        f"Every built-in scene as `picomis-sim export` writes it, at its size scaled to at least "
        f"{args.min_pixels:,} pixels; the exported `direct` integrator's settings (1 light + 1 BSDF "
        f"sample, power heuristic) for both renderers. {args.rounds} interleaved rounds (seeds "
        f"0..{args.rounds - 1}); relative MSE (mean over rounds) outside the emitters against a reference "
        f"independent of picomis (per scene below); render time only (range over rounds); efficiency "
        f"range over rounds, ratio of medians. Machine: {os.cpu_count()} cores, {cpu_name()}, load "
        f"average {load_before:.2f} before the run, {', '.join(f'{x:.2f}' for x in loads)} at the start "
        f"of each round, {load_after:.2f} after. Mitsuba {mi.__version__} `llvm_ad_rgb`. "
        f"{time.perf_counter() - t0:.0f} s in all. Written by `scripts/vs-mitsuba.sh` "
        f"(`scripts/vs-mitsuba/compare.py`, whose docstring states the method)."
    )
    text = "\n\n".join(
        ["# picomis against Mitsuba 3 (equal spp)", header,
         "## Summary: the best of each, per scene", summary_table(scenes)]
        + [scene_table(s) for s in scenes]
    )
    print()
    print(text)
    with open(args.out, "w") as f:
        f.write(text + "\n")
    print(f"-> {args.out}")
    losses = [s.name for s in scenes if best(s, False)[1] < best(s, True)[1]]
    print(f"picomis loses on: {', '.join(losses) or 'none'}")


if __name__ == "__main__":
    sys.exit(main())
