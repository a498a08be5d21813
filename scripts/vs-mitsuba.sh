#!/usr/bin/env bash
# picomis against Mitsuba 3 at equal spp, on every built-in scene (Veach first) and on unseen scenes
# (by default the test doubles tests/scenes/diffuse_room.json and glossy_lights.json; --unseen FILE
# names others). picomis's defaults are the headline, the lecture preset a row for scale; every
# Mitsuba sampler (independent, stratified, multijitter, ldsampler at 64 spp; orthogonal at 121);
# 8 interleaved rounds. Per row: relative MSE against a Mitsuba reference independent of picomis,
# its variance and bias^2 apart (with a standard error), whether it agrees with the reference
# (one rule for every row), render time, camera samples per second, efficiency 1 / (relMSE x s).
# The headline ratio per scene, picomis's defaults against Mitsuba's best sampler free of bias, or
# a row saying why there is none; issue 38's efficiency goals as pass/fail lines (not asserted).
# Writes docs/vs-mitsuba.md (keeping its hand-written part). A benchmark, not a test: run it on a
# quiet machine (the page records the load average). About 20 minutes on 2 cores with an empty
# cache (references, about 10 minutes, are cached under target/vs-mitsuba/renders), 8 to 10 with
# a full one. The method in full, with both rules: the docstring of scripts/vs-mitsuba/compare.py.
#
# Installs what it needs: Mitsuba 3 (PyPI) in a venv under target/vs-mitsuba/, and Debian's
# libllvm19 for Mitsuba's llvm_ad_rgb variant (apt-get, as root).
#
# Usage: scripts/vs-mitsuba.sh [compare.py flags]       the comparison (--help lists the flags)
#        scripts/vs-mitsuba.sh --quick [flags]          a check that it runs (a few minutes, small
#                                                       settings; writes target/vs-mitsuba/renders/quick.md)
#        scripts/vs-mitsuba.sh --ldsampler-bias [flags] whether Mitsuba's ldsampler converges to
#                                                       another image than its other samplers
#                                                       (scripts/vs-mitsuba/ldsampler_bias.py)
#        scripts/vs-mitsuba.sh --sphere-bias [flags]    Mitsuba's and picomis's sphere lights against closed
#                                                       forms, and the Veach block where they disagree
#                                                       (scripts/vs-mitsuba/sphere_bias.py)
#        scripts/vs-mitsuba.sh --point-shadows [flags]  point lights' hard shadows in both against an
#                                                       exact f64 tracer, on point_lights's block
#                                                       where they disagree (scripts/vs-mitsuba/point_shadows.py)
#   e.g. scripts/vs-mitsuba.sh --rounds 5 --scenes veach_mis,stress --unseen my_scene.json
#        --add-picomis-config "independent=--sampler independent"
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
work=$root/target/vs-mitsuba
venv=$work/venv

llvm=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1
if [ ! -e "$llvm" ]; then
    if [ "$(id -u)" = 0 ]; then
        apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q libllvm19
    else
        echo "error: $llvm missing: install Debian's libllvm19 (as root)" >&2
        exit 1
    fi
fi
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/python" -c "import mitsuba, numpy" 2>/dev/null || "$venv/bin/pip" install -q mitsuba numpy

cargo build --release -q -p picomis-sim
script=scripts/vs-mitsuba/compare.py
if [ "${1:-}" = --ldsampler-bias ]; then
    script=scripts/vs-mitsuba/ldsampler_bias.py
    shift
elif [ "${1:-}" = --sphere-bias ]; then
    script=scripts/vs-mitsuba/sphere_bias.py
    shift
elif [ "${1:-}" = --point-shadows ]; then
    script=scripts/vs-mitsuba/point_shadows.py
    shift
fi
DRJIT_LIBLLVM_PATH=$llvm "$venv/bin/python" "$script" \
    --picomis "$root/target/release/picomis-sim" \
    --work "$work/renders" \
    "$@"
