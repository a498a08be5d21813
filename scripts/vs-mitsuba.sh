#!/usr/bin/env bash
# picomis against Mitsuba 3 on every built-in scene (Veach first) at equal spp: relative MSE, render
# time and efficiency 1 / (relMSE x s) of each picomis configuration (by default its defaults,
# with light selection by contribution, and with the control variate) and of every Mitsuba sampler
# (independent, stratified, multijitter, ldsampler at 64 spp; orthogonal at 121), interleaved,
# 3 rounds. Each scene is `picomis-sim export`'s Mitsuba XML, checked to converge to picomis'
# image; its reference is Mitsuba's converged image (multijitter passes, more for Veach and
# lambert_sphere and stress, whose tiny sphere light it renders as a point light; cached under target/vs-mitsuba/renders). Prints the tables and writes docs/vs-mitsuba.md (one table
# per scene and a summary). A benchmark, not a test: run it on a quiet machine (the tables record the load average).
# The method in full: the docstring of scripts/vs-mitsuba/compare.py.
#
# Installs what it needs: Mitsuba 3 (PyPI) in a venv under target/vs-mitsuba/, and Debian's
# libllvm19 for Mitsuba's llvm_ad_rgb variant (apt-get, as root).
#
# Usage: scripts/vs-mitsuba.sh [compare.py flags, e.g. --rounds 5 --scenes veach_mis,stress
#        --add-picomis-config "independent=--sampler independent"
#        --picomis-config "sobol=--sampler sobol" --picomis-config "pcg=--sampler independent"]
#        (scripts/vs-mitsuba.sh --help lists them)
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
DRJIT_LIBLLVM_PATH=$llvm "$venv/bin/python" scripts/vs-mitsuba/compare.py \
    --picomis "$root/target/release/picomis-sim" \
    --work "$work/renders" \
    --out docs/vs-mitsuba.md \
    "$@"
