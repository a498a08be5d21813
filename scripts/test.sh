#!/usr/bin/env bash
# The one test command of picomis (README: "Test"). CI runs exactly this (.ci/run).
# It installs what it needs (rustup targets and components, QEMU from Debian's packages), then:
# format, lints, docs, all host tests, kernel cross-builds for Cortex-M, firmware under QEMU.
set -euo pipefail
cd "$(dirname "$0")/.."

step() { printf '\n==> %s\n' "$*"; }

step "toolchain: targets and components"
rustup component add rustfmt clippy >/dev/null 2>&1 || true
installed=$(rustup target list --installed)
for t in thumbv7em-none-eabihf thumbv6m-none-eabi; do
  grep -qx "$t" <<<"$installed" || rustup target add "$t"
done

step "Debian packages for the view window: SDL2, Xvfb, ImageMagick (import)"
missing=()
command -v Xvfb >/dev/null || missing+=(xvfb)
command -v import >/dev/null || missing+=(imagemagick)
dpkg -s libsdl2-dev >/dev/null 2>&1 || missing+=(libsdl2-dev)
if [ ${#missing[@]} -gt 0 ]; then
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
fi

step "cargo fmt --check"
cargo fmt --all -- --check

step "cargo clippy -D warnings (host crates, all targets)"
cargo clippy --all-targets -- -D warnings
cargo clippy -p picomis-sim --all-targets --features window -- -D warnings

step "kernel: no f64, no alloc"
# Code lines only: doc comments may name f64 (to say why it is avoided).
if grep -rnE '\bf64\b|extern crate alloc|alloc::' kernel/src | grep -vE '^[^:]+:[0-9]+:\s*//'; then
  echo "the kernel must not use f64 or alloc" >&2
  exit 1
fi

step "kernel cross-builds (thumbv7em-none-eabihf, thumbv6m-none-eabi; with and without defmt)"
for t in thumbv7em-none-eabihf thumbv6m-none-eabi; do
  cargo build -p picomis --release --target "$t"
  cargo build -p picomis --release --target "$t" --features defmt
  cargo clippy -p picomis --target "$t" --features defmt -- -D warnings
done

step "docs (-D warnings)"
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps -p picomis -p picomis-format

step "host tests (release: the statistical suites are compute-bound)"
cargo test --release

step "view window under Xvfb: screenshot and simulator dump equal render --out F.rgb565"
cargo test --release -p picomis-sim --features window --test window

if [ -x scripts/firmware.sh ]; then
  step "firmware under QEMU: M4F and M0+, pixels equal to the host's"
  scripts/firmware.sh test
fi
