#!/usr/bin/env bash
# picomis in the browser (web/): build the kernel as WebAssembly, serve the page, and test it in
# headless Chromium against the host's renders, byte for byte.
#
#   scripts/web.sh build        rustup target add wasm32-unknown-unknown (if missing), build
#                               web/wasm (crate picomis-web) and copy it to web/picomis.wasm
#   scripts/web.sh serve [ARGS] build, then `picomis-sim serve ARGS` (default http://127.0.0.1:8000/)
#   scripts/web.sh test         build, install Debian's chromium if missing, serve the page on a
#                               free port, render fixed settings in the page and compare its canvas
#                               (and linear radiance) with `picomis-sim render` (PNG and PFM);
#                               saves a screenshot of the page to <target>/web/page.png
#   scripts/web.sh screenshot   the README's screenshot, docs/web_page.png (Veach scene, 64 spp)
#   scripts/web.sh measure      camera samples per second: the page (one worker) against
#                               `picomis-sim render` on one thread and on all cores
#
# Environment: CARGO_TARGET_DIR (default <root>/target), CHROMIUM (browser binary, default
# chromium), WEB_TIMEOUT (seconds per page load, default 300).
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT"
TD=${CARGO_TARGET_DIR:-$ROOT/target}
case "$TD" in /*) ;; *) TD="$ROOT/$TD" ;; esac
WORK=$TD/web
WASM_TARGET=wasm32-unknown-unknown
SIM=$TD/release/picomis-sim
CHROMIUM=${CHROMIUM:-chromium}
WEB_TIMEOUT=${WEB_TIMEOUT:-300}

say() { printf '%s\n' "$*"; }
die() { printf 'web.sh: %s\n' "$*" >&2; exit 1; }

as_root() {
  if [ "$(id -u)" = 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else "$@"; fi
}

build() {
  rustup target list --installed | grep -qx "$WASM_TARGET" || rustup target add "$WASM_TARGET"
  cargo build --quiet -p picomis-web --target "$WASM_TARGET" --profile wasm
  cp "$TD/$WASM_TARGET/wasm/picomis_web.wasm" web/picomis.wasm
  say "web/picomis.wasm: $(wc -c <web/picomis.wasm) bytes"
}

build_sim() { cargo build --quiet --release -p picomis-sim; }

# Debian's chromium (and python3, which drives it) when missing.
install_chromium() {
  local missing=()
  command -v "$CHROMIUM" >/dev/null || missing+=(chromium)
  command -v python3 >/dev/null || missing+=(python3)
  [ ${#missing[@]} -eq 0 ] && return 0
  say "installing ${missing[*]} (apt-get)"
  as_root apt-get update -qq
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq -o DPkg::Lock::Timeout=600 \
    --no-install-recommends "${missing[@]}" >/dev/null
  command -v "$CHROMIUM" >/dev/null || die "$CHROMIUM is missing after installing chromium"
}

SERVER_PID=
stop_server() { if [ -n "$SERVER_PID" ]; then kill "$SERVER_PID" 2>/dev/null || true; wait "$SERVER_PID" 2>/dev/null || true; fi; }

# Starts `picomis-sim serve` on a free port; sets URL.
start_server() {
  mkdir -p "$WORK"
  "$SIM" serve --port 0 --dir web >"$WORK/serve.log" 2>&1 &
  SERVER_PID=$!
  trap stop_server EXIT
  local i
  for i in $(seq 100); do
    URL=$(sed -n 's|^serving .* at \(http://[^ ]*\) .*|\1|p' "$WORK/serve.log")
    [ -n "$URL" ] && return 0
    kill -0 "$SERVER_PID" 2>/dev/null || { cat "$WORK/serve.log" >&2; die "picomis-sim serve failed"; }
    sleep 0.1
  done
  die "picomis-sim serve did not start"
}

# page NAME QUERY [--screenshot FILE]: loads the page with QUERY&test=1 into $WORK/NAME.json.
page() {
  local name=$1 query=$2
  shift 2
  python3 scripts/web_check.py run "$CHROMIUM" "${URL}?${query}&test=1" "$WORK/$name.json" \
    --timeout "$WEB_TIMEOUT" "$@"
}

# check NAME QUERY HOST-FLAGS...: the page at QUERY against `picomis-sim render HOST-FLAGS`.
check() {
  local name=$1 query=$2
  shift 2
  "$SIM" render "$@" --out "$WORK/$name.png" 2>/dev/null
  "$SIM" render "$@" --out "$WORK/$name.pfm" 2>/dev/null
  page "$name" "$query"
  python3 scripts/web_check.py compare "$WORK/$name.json" "$WORK/$name.png" "$WORK/$name.pfm"
}

test_page() {
  build
  build_sim
  install_chromium
  start_server
  say "page served at $URL by picomis-sim serve; $($CHROMIUM --version 2>/dev/null || true)"
  local failed=0
  # The Veach scene with its own integrator block (power heuristic), in passes of 3 spp
  # (3 + 3 + 2): the passes must add up to the host's single render.
  check veach "scene=veach_mis&spp=8&seed=7&pass=3" veach_mis --spp 8 --seed 7 || failed=1
  # Every control away from its default, adaptive passes.
  check stress \
    "scene=stress&method=cutoff&alpha=0.3&light=2&bsdf=3&selection=power&spheres=area&seed=11&spp=5" \
    stress --mis cutoff --alpha 0.3 --light-samples 2 --bsdf-samples 3 --light-selection power \
    --sphere-sampling area --seed 11 --spp 5 || failed=1
  check points "scene=point_lights&method=balance&beta=3&seed=4294967295&spp=3&pass=1" \
    point_lights --mis balance --seed 4294967295 --spp 3 || failed=1
  # The whole page, for people (the README's picture is `scripts/web.sh screenshot`).
  page shot "scene=veach_mis&spp=16" --screenshot "$WORK/page.png" || failed=1
  [ -s "$WORK/page.png" ] && say "screenshot: $WORK/page.png"
  [ "$failed" = 0 ] || die "the page's pixels differ from the host's"
  say "web: the page's pixels equal the host's"
}

screenshot() {
  build
  build_sim
  install_chromium
  start_server
  page readme "scene=veach_mis&spp=64&seed=0" --screenshot docs/web_page.png
  say "docs/web_page.png"
}

measure() {
  build
  build_sim
  install_chromium
  start_server
  local spp=32 round
  # Alternate browser and native runs, three rounds, so that both see the same machine load.
  for round in 1 2 3; do
    page measure "scene=veach_mis&spp=$spp"
    python3 - "$WORK/measure.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
print(f"browser, one Web Worker: veach_mis: {r['width']}x{r['height']}, {r['spp']} spp, "
      f"{r['samples_per_second'] / 1e6:.2f} M camera samples/s")
PY
    say "native, 1 thread:        $(RAYON_NUM_THREADS=1 "$SIM" render veach_mis --spp $spp --out "$WORK/measure1.png" 2>&1 | tail -1)"
    say "native, $(nproc) threads:       $("$SIM" render veach_mis --spp $spp --out "$WORK/measure2.png" 2>&1 | tail -1)"
  done
}

case "${1:-}" in
  build) build ;;
  serve)
    shift
    build
    cargo run --quiet --release -p picomis-sim -- serve "$@"
    ;;
  test) test_page ;;
  screenshot) screenshot ;;
  measure) measure ;;
  *) sed -n '2,21p' "$0" >&2; exit 2 ;;
esac
