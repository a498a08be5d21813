"""Does Mitsuba 3's ldsampler converge to another image than its other samplers? With standard errors.

Run by `scripts/vs-mitsuba.sh --ldsampler-bias` (which sets up the venv and builds picomis-sim).

The claim (compare.py, REFERENCE_SAMPLER): on the Veach scene, at the left edge of the r = 0.9
light's reflection in the alpha = 0.005 plate (x 266-275, y 112-115 at 384x256), ldsampler's
mean differs from that of the independent, stratified and multijitter samplers (0.158 and 0.727
at x = 271 and 272 against 0.13-0.14 and 0.74-0.75, one run of 8 passes).

Method: the Veach scene as compare.py exports it, at 384x256; for each sampler of SAMPLERS,
`--passes` independent renders (seeds 1,000,000 + pass) of `--spp` spp, cached under the work
folder. Per pixel (RGB averaged), the mean over the passes and its standard error (their spread
over sqrt(passes)).
1. The edge: each sampler's mean and standard error per pixel of the region, and t, the
   difference of ldsampler's mean and multijitter's over its standard error (Welch; passes - 1
   degrees of freedom each).
2. The whole image: compare.py's agreement rule (16x16 blocks, Bonferroni and chi-square) and its
   bias^2 with its standard error, with multijitter's mean in the place of the reference: for
   ldsampler, and for independent as the control (two samplers that are not suspected).
Verdict: reproduced when ldsampler fails the agreement rule against multijitter, its bias^2 is
above two standard errors, and the control passes the rule.
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import compare  # noqa: E402  (sets Mitsuba's variant)

SAMPLERS = ["ldsampler", "multijitter", "independent"]
REGION = dict(x=range(266, 276), y=range(112, 116))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--picomis", required=True, help="picomis-sim binary (for `export`)")
    ap.add_argument("--work", required=True, help="scratch and cache folder")
    ap.add_argument("--passes", type=int, default=16, help="independent passes per sampler")
    ap.add_argument("--spp", type=int, default=256, help="spp per pass")
    ap.add_argument("--out", help="also write the report to this markdown file")
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)

    scene = compare.export_scene(args.picomis, "veach_mis", "veach_mis", "built-in", 384, 256, args.work)
    keep = compare.emitter_mask(scene, scene.xml)
    stacks = {s: compare.mitsuba_stack(scene, s, args.spp, args.passes, args.work, scene.xml) for s in SAMPLERS}
    summaries = {s: compare.summarise(stacks[s], keep) for s in SAMPLERS}

    def se(s):
        return np.sqrt(summaries[s].cvar / summaries[s].n)

    lines = [
        "# Mitsuba 3's ldsampler against its other samplers (Veach, 384x256)",
        "",
        f"{args.passes} independent passes of {args.spp} spp per sampler (seeds 1,000,000 + pass), Mitsuba "
        f"{compare.mi.__version__} `llvm_ad_rgb`; RGB averaged; mean ± standard error over the passes. "
        f"Written by `scripts/vs-mitsuba.sh --ldsampler-bias` (`scripts/vs-mitsuba/ldsampler_bias.py`).",
        "",
        "## The edge of the r = 0.9 light's reflection in the alpha = 0.005 plate",
        "",
        "| x | y | " + " | ".join(SAMPLERS) + " | t (ldsampler - multijitter) |",
        "|---:|---:|" + "---:|" * (len(SAMPLERS) + 1),
    ]
    ld, mj = summaries["ldsampler"], summaries["multijitter"]
    t = (ld.cmean - mj.cmean) / np.sqrt(np.maximum(se("ldsampler") ** 2 + se("multijitter") ** 2, 1e-300))
    for y in REGION["y"]:
        for x in REGION["x"]:
            cells = [f"{summaries[s].cmean[y, x]:.4f} ± {se(s)[y, x]:.4f}" for s in SAMPLERS]
            lines.append(f"| {x} | {y} | " + " | ".join(cells) + f" | {t[y, x]:+.1f} |")
    region_t = t[REGION["y"].start : REGION["y"].stop, REGION["x"].start : REGION["x"].stop]
    lines += ["", f"Pixels of the region with \\|t\\| > 4: {int((np.abs(region_t) > 4).sum())} of {region_t.size}.",
              "", "## The whole image, against multijitter's mean", "",
              "| sampler | agrees with multijitter (compare.py's rule) | bias² ± SE | variance (one pass) |",
              "|---|---|---:|---:|"]
    verdicts = {}
    for s in ["ldsampler", "independent"]:
        a = compare.agreement(summaries[s], mj, keep)
        v, b, b_se = compare.bias_and_variance(summaries[s], mj, keep)
        verdicts[s] = (a["agrees"], b, b_se)
        lines.append(f"| {s} | {compare.describe_agreement(a)} | {b:.2g} ± {b_se:.1g} | {v:.3g} |")
    ld_agrees, ld_b, ld_se = verdicts["ldsampler"]
    reproduced = not ld_agrees and ld_b > 2 * ld_se and verdicts["independent"][0]
    lines += ["", "Verdict: " + ("**reproduced**: ldsampler's mean differs from multijitter's, and independent's "
                                 "does not." if reproduced else
                                 "**not reproduced** at this precision (see the table).")]
    compare.report("\n".join(lines), args.out)


if __name__ == "__main__":
    sys.exit(main())
