"""picomis against Mitsuba 3 on the Veach scene, at equal spp: relative MSE, render time, efficiency.

Run by scripts/vs-mitsuba.sh (which sets up the venv and builds picomis-sim); see there.

- Every renderer renders the Veach scene at WxH with 1 light + 1 BSDF sample and the power heuristic.
- Rounds are interleaved: in each round picomis renders, then every Mitsuba sampler.
- Only render time counts: Mitsuba renders each sampler once to compile its kernels (JIT), then
  the timed render runs in the same process; picomis' time is the render time it prints (scene
  loading and file writing excluded).
- The error is the relative MSE, mean of (I - R)^2 / (R^2 + 0.01) over pixels and RGB channels,
  against the ~37,000-spp Mitsuba reference, leaving out the pixels that see an emitter (found by
  a Mitsuba path tracer of depth 1, which renders only the emission seen directly).
- Efficiency is 1 / (relative MSE x seconds).
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import time

import drjit as dr
import mitsuba as mi
import numpy as np

mi.set_variant("llvm_ad_rgb")

# (sampler, spp): orthogonal needs the square of a prime.
MITSUBA = [("independent", 64), ("stratified", 64), ("multijitter", 64), ("ldsampler", 64), ("orthogonal", 121)]


def rel_mse(img, ref, keep):
    e = (img - ref) ** 2 / (ref**2 + 0.01)
    return float(e[keep].mean())


def load_exr(path):
    return np.array(mi.Bitmap(str(path)), dtype=np.float64)[:, :, :3]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--picomis", required=True, help="picomis-sim binary")
    ap.add_argument("--xml", required=True)
    ap.add_argument("--json", required=True, help="picomis scene")
    ap.add_argument("--reference", required=True)
    ap.add_argument("--out", required=True, help="markdown table to write")
    ap.add_argument("--work", required=True, help="scratch folder")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--width", type=int, default=384)
    ap.add_argument("--height", type=int, default=256)
    ap.add_argument("--picomis-config", action="append", default=[],
                    help="NAME=FLAGS: a picomis configuration (repeatable; default: the defaults)")
    args = ap.parse_args()

    load_before = os.getloadavg()[0]
    ref = load_exr(args.reference)
    assert ref.shape[:2] == (args.height, args.width), ref.shape
    common = dict(resx=args.width, resy=args.height)

    # Pixels that see an emitter: a path tracer of depth 1 renders only the emission seen directly.
    s = mi.load_file(args.xml, spp=256, sampler="stratified", **common)
    emission_only = mi.load_dict({"type": "path", "max_depth": 1})
    emitted = np.array(mi.render(s, spp=256, integrator=emission_only), dtype=np.float64)[:, :, :3]
    keep = np.broadcast_to((emitted.max(axis=2) <= 0.0)[:, :, None], ref.shape)
    print(f"{(~keep[:, :, 0]).sum()} of {args.width * args.height} pixels see an emitter and are left out")

    scenes = {}
    for name, spp in MITSUBA:
        scene = mi.load_file(args.xml, spp=spp, sampler=name, **common)
        dr.eval(mi.render(scene, spp=spp, seed=1000))  # compile (JIT) once, untimed
        scenes[name] = (scene, spp)

    # The defaults, and the defaults with light selection by contribution (not the default: it
    # costs O(lights) per shading point, which does not pay on every scene).
    configs = [("picomis", []), ("picomis, lights by contribution", ["--light-selection", "contribution"])]
    if args.picomis_config:
        configs = [(c.split("=", 1)[0], c.split("=", 1)[1].split()) for c in args.picomis_config]
    rows = {f"{name}": [] for name, _ in configs}
    rows.update({f"Mitsuba 3, {n}": [] for n, _ in MITSUBA})
    spps = {f"{name}": args.spp for name, _ in configs}
    spps.update({f"Mitsuba 3, {n}": spp for n, spp in MITSUBA})
    os.makedirs(args.work, exist_ok=True)
    for r in range(args.rounds):
        for c, (name, flags) in enumerate(configs):
            out = os.path.join(args.work, f"picomis{c}_{r}.exr")
            cmd = [args.picomis, "render", args.json, "--spp", str(args.spp), "--seed", str(r),
                   "--width", str(args.width), "--height", str(args.height), "--out", out] + flags
            p = subprocess.run(cmd, capture_output=True, text=True, check=True)
            secs = float(re.search(r", ([0-9.]+) s, ", p.stderr).group(1))
            rows[name].append((rel_mse(load_exr(out), ref, keep), secs))
            print(f"round {r}: {name}: relMSE {rows[name][-1][0]:.5f}, {secs:.3f} s", flush=True)
        for name, (scene, spp) in scenes.items():
            t0 = time.perf_counter()
            img = mi.render(scene, spp=spp, seed=r)
            dr.eval(img)
            dr.sync_thread()
            secs = time.perf_counter() - t0
            key = f"Mitsuba 3, {name}"
            rows[key].append((rel_mse(np.array(img, dtype=np.float64)[:, :, :3], ref, keep), secs))
            print(f"round {r}: {key}: relMSE {rows[key][-1][0]:.5f}, {secs:.3f} s", flush=True)

    def eff(v):
        return [1.0 / (e * s) for e, s in v]

    best_mitsuba = max(statistics.median(eff(v)) for k, v in rows.items() if k.startswith("Mitsuba"))
    lines = [
        f"| renderer, sampler | spp | relative MSE | render s | efficiency 1/(relMSE x s) | vs Mitsuba's best |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for k, v in rows.items():
        errs, secs, effs = [e for e, _ in v], [s for _, s in v], eff(v)
        lines.append(
            f"| {k} | {spps[k]} | {statistics.mean(errs):.5f} | {min(secs):.3f}-{max(secs):.3f} | "
            f"{min(effs):,.0f}-{max(effs):,.0f} | {statistics.median(effs) / best_mitsuba:.2f}x |"
        )
    cpu = "unknown"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    header = (
        f"Veach scene, {args.width}x{args.height}, 1 light + 1 BSDF sample, power heuristic; "
        f"{args.rounds} interleaved rounds (seeds 0..{args.rounds - 1}); relative MSE (mean over rounds) "
        f"outside the emitters against the ~37,000-spp Mitsuba 3 reference; render time only "
        f"(range over rounds); efficiency range over rounds, ratio of medians. "
        f"Machine: {os.cpu_count()} cores, {cpu}, load average before the run "
        f"{load_before:.2f}. Mitsuba {mi.__version__} `llvm_ad_rgb`. "
        f"Written by `scripts/vs-mitsuba.sh`."
    )
    table = "\n".join(lines)
    print()
    print(table)
    with open(args.out, "w") as f:
        f.write("# picomis against Mitsuba 3 (equal spp)\n\n" + header + "\n\n" + table + "\n")
    print(f"-> {args.out}")


if __name__ == "__main__":
    sys.exit(main())
