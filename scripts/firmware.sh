#!/usr/bin/env bash
# picomis firmware: build for Cortex-M4F (STM32F405, QEMU netduinoplus2), Cortex-M0
# (nRF51822 / micro:bit, QEMU microbit) and RISC-V RV32IMC (FE310 / HiFive1, QEMU sifive_e), run
# under QEMU, compare the framebuffer with the host's render byte for byte, and measure code
# size, RAM, stack and instructions per camera sample.
#
#   scripts/firmware.sh setup     install what is missing (rustup targets, qemu-system-arm,
#                                 qemu-system-misc for qemu-system-riscv32)
#   scripts/firmware.sh test      build all variants, run them under QEMU, compare pixels and
#                                 the digest of the f32 HDR estimates with the host's, check the
#                                 ELFs for f64 routines and allocator symbols (scripts/symbols.sh);
#                                 last line: "firmware: N passed, M failed"
#   scripts/firmware.sh measure   sizes, static RAM, peak stack, instructions per camera sample;
#                                 writes firmware/budget.json and the table of docs/firmware.md from it
#   scripts/firmware.sh budget    the same measurement, checked against firmware/budget.json
#                                 (fails on a rise of more than 2 %; writes nothing)
#   scripts/firmware.sh lint      cargo fmt --check and clippy -D warnings for every target (the
#                                 firmware, picomis-embedded, picomis-softfloat)
#   scripts/firmware.sh boards    the board examples (boards/*, crates of their own) build for
#                                 their targets, clippy -D warnings and rustfmt clean; they
#                                 cannot run here (no probe)
#
# Environment: CARGO_TARGET_DIR (default <root>/target), PICOMIS_SIM (host renderer binary,
# default: built with `cargo build --release -p picomis-sim`), FIRMWARE_WORK (output folder,
# default <target dir>/firmware-work), QEMU_TIMEOUT (seconds per run, default 180).
set -uo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
FW="$ROOT/firmware"
TD=${CARGO_TARGET_DIR:-$ROOT/target}
case "$TD" in /*) ;; *) TD="$ROOT/$TD" ;; esac
WORK=${FIRMWARE_WORK:-$TD/firmware-work}
QEMU_TIMEOUT=${QEMU_TIMEOUT:-180}
M4=thumbv7em-none-eabihf
M0=thumbv6m-none-eabi
RV=riscv32imc-unknown-none-elf
VEACH=scenes/veach_mis.json
# The size-optimised RV32IMC build's target features (added to firmware/.cargo/config.toml's).
RV_SMALL_CONFIG="target.riscv32imc-unknown-none-elf.rustflags=['-C', 'target-feature=+relax,+save-restore']"
LAMBERT=scenes/lambert_sphere.json
# Quad lights sampled in solid angle warped by the cosine (its integrator block asks for them).
PANEL=tests/scenes/panel_room.json

say() { printf '%s\n' "$*"; }
step() { printf '\n==> %s\n' "$*"; }
die() { printf 'firmware.sh: %s\n' "$*" >&2; exit 1; }

as_root() {
  if [ "$(id -u)" = 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else "$@"; fi
}

apt_install() { # packages...
  say "installing $* (apt-get)"
  as_root apt-get update -qq || return 1
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@" >/dev/null
}

setup() { # [binutils]
  local installed t missing=()
  command -v rustup >/dev/null || die "rustup is required"
  installed=$(rustup target list --installed)
  for t in $M4 $M0 $RV; do
    grep -qx "$t" <<<"$installed" || rustup target add "$t" || die "rustup target add $t failed"
  done
  command -v qemu-system-arm >/dev/null || missing+=(qemu-system-arm)
  command -v qemu-system-riscv32 >/dev/null || missing+=(qemu-system-misc)
  if [ "${1:-}" = binutils ]; then
    command -v arm-none-eabi-size >/dev/null || missing+=(binutils-arm-none-eabi)
  fi
  if [ ${#missing[@]} -gt 0 ]; then
    apt_install "${missing[@]}" || die "could not install ${missing[*]}"
  fi
  command -v qemu-system-arm >/dev/null || die "qemu-system-arm is missing"
  command -v qemu-system-riscv32 >/dev/null || die "qemu-system-riscv32 is missing"
}

machine_of() { case "$1" in $M4) echo netduinoplus2 ;; $M0) echo microbit ;; $RV) echo sifive_e ;; esac; }
qemu_of() { case "$1" in $RV) echo qemu-system-riscv32 ;; *) echo qemu-system-arm ;; esac; }

# build NAME TARGET FEATURES-ARGS SCENE W H SPP SEED: builds one variant, copies its ELF to
# $WORK/NAME.elf. FEATURES-ARGS is e.g. "", "--features rtt", "--no-default-features --features rtt".
# With PRESET set (lecture, best): that preset's settings instead of the scene file's block (the
# host render of check_render takes --preset too). PROFILE: the Cargo profile (default firmware;
# firmware-small is the same optimised for size).
build() {
  local name=$1 target=$2 feats=$3 scene=$4 w=$5 h=$6 spp=$7 seed=$8 config=()
  mkdir -p "$WORK"
  # RV32IMC built for size: functions save and restore their registers through shared routines
  # (LLVM's save-restore, GCC's -msave-restore; firmware/src/arch/riscv_save_restore.s).
  if [ "${PROFILE:-firmware}" = firmware-small ] && [ "$target" = "$RV" ]; then
    config=(--config "$RV_SMALL_CONFIG")
  fi
  # shellcheck disable=SC2086
  if ! (cd "$FW" && CARGO_TARGET_DIR="$TD" PICOMIS_SCENE="$scene" PICOMIS_WIDTH="$w" PICOMIS_HEIGHT="$h" \
      PICOMIS_SPP="$spp" PICOMIS_SEED="$seed" PICOMIS_OUT="$name.rgb565" PICOMIS_PRESET="${PRESET:-}" \
      cargo build --profile "${PROFILE:-firmware}" "${config[@]}" --quiet --target "$target" $feats) >"$WORK/$name.build.log" 2>&1; then
    cat "$WORK/$name.build.log" >&2
    return 1
  fi
  cp "$TD/$target/${PROFILE:-firmware}/picomis-firmware" "$WORK/$name.elf"
}

# run NAME TARGET [extra qemu args]: runs $WORK/NAME.elf under QEMU in $WORK (output file and
# log land there); returns QEMU's exit status (the firmware's SYS_EXIT_EXTENDED code).
run_qemu() {
  local name=$1 target=$2
  shift 2
  rm -f "$WORK/$name.rgb565"
  (cd "$WORK" && timeout "$QEMU_TIMEOUT" "$(qemu_of "$target")" -machine "$(machine_of "$target")" -nographic \
    -monitor none -serial null -semihosting-config enable=on,target=native -icount shift=0 "$@" \
    -kernel "$name.elf") >"$WORK/$name.log" 2>&1
}

# The host renderer, built once (release) unless PICOMIS_SIM names one; sets SIM.
SIM=
prepare_host_sim() {
  if [ -n "${PICOMIS_SIM:-}" ]; then
    SIM=$PICOMIS_SIM
  elif (cd "$ROOT" && CARGO_TARGET_DIR="$TD" cargo build --release --quiet -p picomis-sim); then
    SIM="$TD/release/picomis-sim"
  else
    say "could not build picomis-sim"
  fi
}

PASSED=0
FAILED=0
pass() { PASSED=$((PASSED + 1)); say "PASS $*"; }
fail() { FAILED=$((FAILED + 1)); say "FAIL $*"; }

# arith_of FEATURES: the host's --arith for a firmware build with FEATURES (fixed with the
# `fixed` feature).
arith_of() { case " $1 " in *" --features fixed "* | *",fixed "* | *" --features fixed,"*) echo fixed ;; *) echo f32 ;; esac; }

# check_render NAME TARGET FEATURES SCENE W H SPP SEED: build, run under QEMU, check the exit
# status and the log, and compare the framebuffer with the host's render of the same scene (in
# fixed point with the `fixed` feature: `picomis-sim render --arith fixed`). Semihosting-text
# builds ("" and "--features fixed") also compare the HDR digest.
check_render() {
  local name=$1 target=$2 feats=$3 scene=$4 w=$5 h=$6 spp=$7 seed=$8 rc arith text=0
  arith=$(arith_of "$feats")
  { [ "$feats" = "" ] || [ "$feats" = "--features fixed" ]; } && text=1
  if ! build "$@"; then
    fail "$name: build ($target $feats)"
    return
  fi
  run_qemu "$name" "$target"
  rc=$?
  if [ $rc -ne 0 ]; then
    fail "$name: QEMU exit status $rc (log: $WORK/$name.log)"
    tail -n 20 "$WORK/$name.log"
    return
  fi
  if [ $text = 1 ] && ! grep -q "^rendered $((w * h)) pixels" "$WORK/$name.log"; then
    fail "$name: no render statistics in the log"
    return
  fi
  if [ "$(stat -c %s "$WORK/$name.rgb565" 2>/dev/null)" != "$((w * h * 2))" ]; then
    fail "$name: framebuffer file missing or not $((w * h * 2)) bytes"
    return
  fi
  if [ -z "$SIM" ]; then
    fail "$name: no host renderer (picomis-sim)"
    return
  fi
  if ! "$SIM" render "$ROOT/$scene" --width "$w" --height "$h" --spp "$spp" --seed "$seed" \
      --arith "$arith" ${PRESET:+--preset "$PRESET"} --out "$WORK/$name.host.rgb565" --digest >"$WORK/$name.host.log" 2>&1; then
    fail "$name: host render failed: $(tail -n 3 "$WORK/$name.host.log")"
    return
  fi
  if cmp "$WORK/$name.rgb565" "$WORK/$name.host.rgb565"; then
    pass "$name: $target ${feats:-(qemu)} $scene ${w}x${h} spp $spp seed $seed: QEMU framebuffer == host (--arith $arith)"
  else
    fail "$name: QEMU framebuffer differs from the host render (--arith $arith)"
  fi
  if [ $text = 1 ]; then
    check_digest "$name"
  fi
}

# check_digest NAME: the f32 HDR estimates of every pixel (all parts), compared through the
# digest the firmware logs (`hdr-digest N`) and the one `picomis-sim render --digest` printed.
check_digest() {
  local name=$1 dev host
  dev=$(sed -n 's/^hdr-digest \([0-9]*\)$/\1/p' "$WORK/$name.log")
  host=$(sed -n 's/^hdr-digest \([0-9]*\)$/\1/p' "$WORK/$name.host.log")
  if [ -z "$dev" ] || [ -z "$host" ]; then
    fail "$name: HDR digest missing (firmware '${dev}', host '${host}')"
  elif [ "$dev" = "$host" ]; then
    pass "$name: HDR estimates (f32 bits of every part of every pixel) == host: digest $dev"
  else
    fail "$name: HDR estimates differ from the host's: digest $dev on the device, $host on the host"
  fi
}

# The built-in scenes, as `picomis-sim scenes` lists them (one definition: the host's list).
builtin_scenes() {
  [ -n "$SIM" ] && "$SIM" scenes | awk 'NF {print $1}'
}

# The host's digests of the soft-float check (firmware/src/fpcheck.rs), computed by the
# firmware crate's host stub with the host's own f32; sets SOFTFLOAT_HOST.
SOFTFLOAT_HOST=
prepare_softfloat_host() {
  if (cd "$ROOT" && CARGO_TARGET_DIR="$TD" cargo build --release --quiet -p picomis-firmware); then
    SOFTFLOAT_HOST=$("$TD/release/picomis-firmware" softfloat-digest)
  else
    say "could not build the firmware's host stub (picomis-firmware)"
  fi
}

# check_softfloat NAME TARGET: builds the softfloat-check firmware, which runs the soft-float
# routines on the operand pairs of fpcheck.rs and compares each result with compiler-builtins
# (exit status 6 on a mismatch), the kernel's dot product with glam's through the library,
# and compares its digest lines with the host's.
check_softfloat() {
  local name=$1 target=$2 line
  if ! build "$name" "$target" "--features softfloat-check" "$VEACH" 8 8 1 0; then
    fail "$name: build ($target softfloat-check)"
    return
  fi
  run_qemu "$name" "$target"
  local rc=$?
  line=$(grep -E '^softfloat (dot )?digest:' "$WORK/$name.log")
  if [ $rc -ne 0 ]; then
    fail "$name: QEMU exit status $rc: $(grep -m3 '^softfloat' "$WORK/$name.log" | tr '\n' ' ')"
  elif [ -z "$SOFTFLOAT_HOST" ] || [ "$line" != "$SOFTFLOAT_HOST" ]; then
    fail "$name: soft-float digests differ: target '$line', host '$SOFTFLOAT_HOST'"
  else
    pass "$name: $target soft float == compiler-builtins (bit for bit) and == host f32 ($(printf '%s' "$line" | tr '\n' ' '))"
  fi
}

# check_unrepresentable NAME TARGET SCENE: the fixed-point firmware of a scene the format cannot
# represent exits with status 7 and logs the shape and the reason (no panic, no render).
check_unrepresentable() {
  local name=$1 target=$2 scene=$3 rc
  if ! build "$name" "$target" "--features fixed" "$scene" 16 12 1 0; then
    fail "$name: build ($target --features fixed)"
    return
  fi
  run_qemu "$name" "$target"
  rc=$?
  if [ $rc -eq 7 ] && grep -q '^error: fixed point cannot represent shape [0-9]* of scene' "$WORK/$name.log"; then
    pass "$name: $target --features fixed $scene: rejected (status 7): $(grep -m1 '^error:' "$WORK/$name.log")"
  else
    fail "$name: expected status 7 and the shape in the log, got status $rc (log: $WORK/$name.log)"
  fi
}

check_build() { # NAME TARGET FEATURES
  if build "$1" "$2" "$3" "$VEACH" 64 48 1 0; then
    pass "$1: $2 $3 builds"
  else
    fail "$1: $2 $3 does not build"
  fi
}

# The strategies beyond the lecture's that the Veach scene uses with the best preset (its file
# names none: the defaults): a sample of every light (five lights), lobe mixing (near-mirror
# plates), the unblocked control variate (a Lambertian floor under sphere lights).
VEACH_BEST_STRATEGIES=every,lobe,control-variate

# check_strategies LIST NAME...: the linked firmware carries the code of exactly the strategies
# beyond the lecture's that LIST names (scripts/symbols.sh --strategies).
check_strategies() {
  local want=$1 n
  shift
  for n in "$@"; do
    if "$ROOT/scripts/symbols.sh" --strategies "$want" "$WORK/$n.elf" >"$WORK/$n.strategies.log" 2>&1; then
      pass "$n: carries the code of the strategies beyond the lecture's it uses ($want), no other"
    else
      fail "$n: $(head -n 3 "$WORK/$n.strategies.log" | tr '\n' ' ')"
    fi
  done
}

# check_symbols NAME...: no f64 routine and no allocator symbol in the linked firmware.
check_symbols() {
  local n
  for n in "$@"; do
    if "$ROOT/scripts/symbols.sh" "$WORK/$n.elf" >"$WORK/$n.symbols.log" 2>&1; then
      pass "$n: no f64 routine, no allocator symbol in the ELF"
    else
      fail "$n: $(head -n 3 "$WORK/$n.symbols.log")"
    fi
  done
}

cmd_test() {
  local start=$SECONDS scenes=("$VEACH")
  setup
  [ -f "$ROOT/$LAMBERT" ] && scenes+=("$LAMBERT")
  step "firmware: host renderer (picomis-sim, release)"
  prepare_host_sim
  prepare_softfloat_host
  step "firmware: builds, QEMU runs and host comparison (work dir $WORK)"
  # Cortex-M4F, 160x120.
  check_render m4-veach $M4 "" "$VEACH" 160 120 1 0
  check_render m4-veach-rtt $M4 "--features rtt" "$VEACH" 160 120 1 0
  [ ${#scenes[@]} -gt 1 ] && check_render m4-lambert $M4 "" "$LAMBERT" 160 120 1 0
  check_render m4-veach-spp $M4 "" "$VEACH" 48 32 3 7
  check_render m4-panel $M4 "" "$PANEL" 40 30 2 5
  local b
  for b in $(builtin_scenes); do
    check_render "m4-scene-$b" $M4 "" "scenes/$b.json" 40 30 2 5
  done
  check_build m4-board-rtt $M4 "--no-default-features --features rtt"
  # Cortex-M0, 64x48 (16 KiB RAM); its hand-written soft float first.
  check_softfloat m0-softfloat $M0
  check_softfloat rv-softfloat $RV
  check_render m0-veach $M0 "" "$VEACH" 64 48 1 0
  check_render m0-veach-rtt $M0 "--features rtt" "$VEACH" 64 48 1 0
  [ ${#scenes[@]} -gt 1 ] && check_render m0-lambert $M0 "" "$LAMBERT" 64 48 1 0
  check_render m0-veach-spp $M0 "" "$VEACH" 24 16 3 9
  check_render m0-panel $M0 "" "$PANEL" 24 16 2 5
  check_build m0-board-rtt $M0 "--no-default-features --features rtt"
  # Fixed-point ray queries (feature fixed) on the cores without an FPU.
  check_render m0-fixed-veach $M0 "--features fixed" "$VEACH" 64 48 1 0
  [ ${#scenes[@]} -gt 1 ] && check_render m0-fixed-lambert $M0 "--features fixed" "$LAMBERT" 64 48 1 0
  check_render m0-fixed-veach-spp $M0 "--features fixed" "$VEACH" 24 16 3 9
  check_render m0-fixed-stress $M0 "--features fixed" scenes/stress.json 24 16 2 5
  check_unrepresentable m0-fixed-tiny-light $M0 tests/scenes/tiny_light.json
  # RISC-V RV32IMC, 64x48 (FE310: 16 KiB RAM).
  check_render rv-veach $RV "" "$VEACH" 64 48 1 0
  check_render rv-veach-rtt $RV "--features rtt" "$VEACH" 64 48 1 0
  [ ${#scenes[@]} -gt 1 ] && check_render rv-lambert $RV "" "$LAMBERT" 64 48 1 0
  check_render rv-panel $RV "" "$PANEL" 24 16 2 5
  check_build rv-board-rtt $RV "--no-default-features --features rtt"
  check_render rv-fixed-veach $RV "--features fixed" "$VEACH" 64 48 1 0
  # The lecture's settings (PICOMIS_PRESET=lecture): the same pixels as the host's with --preset
  # lecture, and none of the strategies beyond the lecture's in the linked firmware; Veach's own
  # settings (the best preset's) carry exactly theirs.
  PRESET=lecture check_render m4-veach-lecture $M4 "" "$VEACH" 160 120 1 0
  PRESET=lecture check_render m0-veach-lecture $M0 "" "$VEACH" 64 48 1 0
  PRESET=lecture check_render rv-veach-lecture $RV "" "$VEACH" 64 48 1 0
  check_strategies none m4-veach-lecture m0-veach-lecture rv-veach-lecture
  # The builds for 32 KiB parts (profile firmware-small; on RV32IMC with save-restore too) on the
  # soft-float cores: the same pixels.
  PROFILE=firmware-small check_render m0-veach-small $M0 "" "$VEACH" 64 48 1 0
  PROFILE=firmware-small check_render rv-veach-small $RV "" "$VEACH" 64 48 1 0
  check_strategies "$VEACH_BEST_STRATEGIES" m4-veach m0-veach rv-veach m0-veach-small rv-veach-small
  check_symbols m4-veach m4-board-rtt m0-veach m0-board-rtt rv-veach rv-board-rtt m0-fixed-veach rv-fixed-veach
  say "firmware tests took $((SECONDS - start)) s"
  say "firmware: $PASSED passed, $FAILED failed"
  [ "$FAILED" -eq 0 ]
}

# Section sizes of an ELF: prints "vector text rodata data bss uninit" (rodata includes the
# RISC-V build's .eh_frame, which is in flash too). arm-none-eabi-size reads RISC-V ELFs too.
sections() {
  arm-none-eabi-size -A "$1" | awk '
    $1==".vector_table"{v=$2} $1==".text"{t=$2} $1==".rodata"||$1==".eh_frame"{r+=$2} $1==".data"{d=$2}
    $1==".bss"{b=$2} $1==".uninit"{u=$2}
    END{printf "%d %d %d %d %d %d\n", v, t, r, d, b, u}'
}

symbol_size() { # ELF SYMBOL-SUBSTRING
  local hex
  hex=$(arm-none-eabi-nm -S -C "$1" | awk -v s="$2" 'index($0, s) && NF>=4 {print $2; exit}')
  echo $((16#${hex:-0}))
}

report_size() { # NAME TARGET LABEL
  local elf="$WORK/$1.elf" v t r d b u fb ram
  read -r v t r d b u < <(sections "$elf")
  fb=$(symbol_size "$elf" "FRAMEBUFFER")
  fb=${fb:-0}
  ram=$((d + b + u - fb))
  printf '%-34s text %6d  rodata %5d  vectors %4d  flash %6d | data %4d  bss %6d  framebuffer %6d  RAM besides framebuffer %5d\n' \
    "$3" "$t" "$r" "$v" $((v + t + r + d)) "$d" "$b" "$fb" "$ram"
}

# The cores measured: label, build-name prefix, target, film, instruction target per camera sample.
CORES=("M4F m4 $M4 160x120 2000" "M0 m0 $M0 64x48 20000" "RV32IMC rv $RV 64x48 20000")
# The cores measured with the fixed-point ray queries (feature fixed) too.
FIXED_CORES=("M0 m0 $M0 64x48 20000" "RV32IMC rv $RV 64x48 20000")

# Runs the named builds for TARGET under QEMU and prints each one's stack peak.
stack_peaks() { # TARGET NAME...
  local target=$1 n
  shift
  for n in "$@"; do
    run_qemu "$n" "$target" || die "$n: QEMU exit status $? (log $WORK/$n.log)"
    printf '%-18s %s\n' "$n" "$(grep -m1 '^stack peak:' "$WORK/$n.log")"
  done
}

cmd_measure() {
  setup binutils
  local c core pre target film goal n
  step "measure: builds (profile firmware: lto fat, codegen-units 1)"
  for c in "${CORES[@]}"; do
    read -r core pre target film goal <<<"$c"
    PRESET=lecture build "$pre-size" "$target" "" "$VEACH" "${film%x*}" "${film#*x}" 1 0 || die "build failed"
    PRESET=lecture build "$pre-size-board" "$target" "--no-default-features --features rtt" "$VEACH" "${film%x*}" "${film#*x}" 1 0 ||
      die "build failed"
    # The best preset (the defaults): its board build and its instruction count.
    PRESET=best build "$pre-best-size-board" "$target" "--no-default-features --features rtt" "$VEACH" "${film%x*}" "${film#*x}" 1 0 ||
      die "build failed"
    PRESET=best build "$pre-best-measure" "$target" "--features measure" "$VEACH" 64 48 1 0 || die "build failed"
    # The same built for size (profile firmware-small, opt-level "z"): the build for 32 KiB parts.
    PRESET=best PROFILE=firmware-small build "$pre-best-small-size-board" "$target" "--no-default-features --features rtt" \
      "$VEACH" "${film%x*}" "${film#*x}" 1 0 || die "build failed"
    PRESET=best PROFILE=firmware-small build "$pre-best-small-measure" "$target" "--features measure" "$VEACH" 64 48 1 0 ||
      die "build failed"
    # Instruction counts: the Veach scene at 64x48, 1 spp, on every core (the same work).
    PRESET=lecture build "$pre-measure" "$target" "--features measure" "$VEACH" 64 48 1 0 || die "build failed"
  done
  # The fixed-point ray queries (feature fixed) on the cores without an FPU.
  for c in "${FIXED_CORES[@]}"; do
    read -r core pre target film goal <<<"$c"
    # The lecture's strategies, like the f32 figures they are compared with.
    PRESET=lecture build "$pre-fixed-size" "$target" "--features fixed" "$VEACH" "${film%x*}" "${film#*x}" 1 0 || die "build failed"
    PRESET=lecture build "$pre-fixed-measure" "$target" "--features measure,fixed" "$VEACH" 64 48 1 0 || die "build failed"
  done

  step "measure: size (bytes; targets: text <= 32768, RAM besides the framebuffer <= 4096)"
  for c in "${CORES[@]}"; do
    read -r core pre target film goal <<<"$c"
    report_size "$pre-size" "$target" "$core qemu (semihosting text) $film"
    report_size "$pre-size-board" "$target" "$core board (defmt-rtt) $film"
  done
  for c in "${FIXED_CORES[@]}"; do
    read -r core pre target film goal <<<"$c"
    report_size "$pre-fixed-size" "$target" "$core fixed qemu (semihosting) $film"
  done

  step "measure: peak stack (stack painting; target <= 4096 bytes)"
  for c in "${CORES[@]}"; do
    read -r core pre target film goal <<<"$c"
    stack_peaks "$target" "$pre-size" "$pre-measure"
  done
  for c in "${FIXED_CORES[@]}"; do
    read -r core pre target film goal <<<"$c"
    stack_peaks "$target" "$pre-fixed-size" "$pre-fixed-measure"
  done

  step "measure: instructions per camera sample (Veach, 1 light + 1 BSDF sample, power heuristic, the lecture's strategies)"
  for c in "${CORES[@]}"; do
    read -r core pre target film goal <<<"$c"
    say "-- $pre-measure ($core)"
    grep '^measure:' "$WORK/$pre-measure.log"
  done
  for c in "${FIXED_CORES[@]}"; do
    read -r core pre target film goal <<<"$c"
    say "-- $pre-fixed-measure ($core, fixed-point ray queries)"
    grep '^measure:' "$WORK/$pre-fixed-measure.log"
  done

  step "measure: summary"
  local per stackline v t r d b u fb figures="$WORK/figures.txt"
  : >"$figures"
  for c in "${CORES[@]}"; do
    read -r core pre target film goal <<<"$c"
    summarize "$core" "$goal" "$pre" "$WORK/$pre-size-board.elf" "board build"
    record_figures "$figures" "$core" "$per" "$t" "$r" $((d + b + u - fb)) "${stackline%% *}"
  done
  # The fixed-point builds: their instructions per camera sample are budgets too.
  for c in "${FIXED_CORES[@]}"; do
    read -r core pre target film goal <<<"$c"
    summarize "$core fixed" "$goal" "$pre-fixed" "$WORK/$pre-fixed-size.elf" "qemu build"
    [ -n "$per" ] || die "$core fixed: no instructions per camera sample"
    printf '%s_fixed_instructions_per_camera_sample %s\n' "$(tr '[:upper:]' '[:lower:]' <<<"$core")" "$per" >>"$figures"
  done
  # The best preset (the defaults), built for speed (best_) and for size (best_small_):
  # instructions per camera sample and the board build's flash.
  local kind key
  for kind in best best-small; do
    key=${kind//-/_}
    for c in "${CORES[@]}"; do
      read -r core pre target film goal <<<"$c"
      run_qemu "$pre-$kind-measure" "$target" || die "$pre-$kind-measure: QEMU exit status $? (log $WORK/$pre-$kind-measure.log)"
      per=$(sed -n 's/^measure: camera_sample: per camera sample \([0-9.]*\) .*/\1/p' "$WORK/$pre-$kind-measure.log")
      [ -n "$per" ] || die "$core $kind: no instructions per camera sample"
      read -r v t r d b u < <(sections "$WORK/$pre-$kind-size-board.elf")
      say "$core, $kind: $per instructions per camera sample; board build: text $t, rodata $r"
      printf '%s_%s_instructions_per_camera_sample %s\n%s_%s_flash_text_bytes %s\n' \
        "$(tr '[:upper:]' '[:lower:]' <<<"$core")" "$key" "$per" "$(tr '[:upper:]' '[:lower:]' <<<"$core")" "$key" "$t" >>"$figures"
    done
  done
  if [ "${1:-}" = check ]; then
    step "budget: figures against firmware/budget.json"
    "$ROOT/scripts/budget.sh" check "$figures"
  else
    step "measure: firmware/budget.json and the table of docs/firmware.md"
    "$ROOT/scripts/budget.sh" write "$figures" && "$ROOT/scripts/budget.sh" readme
  fi
}

# record_figures FILE CORE INSTRUCTIONS TEXT RODATA RAM STACK: one "key value" line per figure
# (read by scripts/budget.sh).
# One core's summary line from its measure and size logs (logs $WORK/PRE-measure.log and
# $WORK/PRE-size.log, sections of ELF); leaves per, t, r, d, b, u, fb and stackline set for the caller.
summarize() {
  local label=$1 goal=$2 pre=$3 elf=$4 build=$5 tile verdict
  per=$(sed -n 's/^measure: camera_sample: per camera sample \([0-9.]*\) .*/\1/p' "$WORK/$pre-measure.log")
  tile=$(sed -n 's/^measure: render_tile: per camera sample \([0-9.]*\) .*/\1/p' "$WORK/$pre-measure.log")
  stackline=$(sed -n 's/^stack peak: \(.*\)/\1/p' "$WORK/$pre-size.log")
  read -r v t r d b u < <(sections "$elf")
  fb=$(symbol_size "$elf" FRAMEBUFFER)
  verdict="over the target"
  awk -v p="${per:-1e99}" -v g="$goal" 'BEGIN{exit !(p <= g)}' && verdict="within the target"
  say "$label: ${per:-?} instructions per camera sample, target $goal: $verdict" \
    "(${tile:-?} with tone map and store);" \
    "$build: text $t, rodata $r, data $d, bss $b (framebuffer $fb, other RAM $((d + b + u - fb)));" \
    "stack $stackline"
}

record_figures() {
  local file=$1 core
  core=$(tr '[:upper:]' '[:lower:]' <<<"$2")
  [ -n "$3" ] && [ -n "$7" ] || die "$2: a figure is missing (instructions '$3', stack '$7')"
  printf '%s_instructions_per_camera_sample %s\n%s_flash_text_bytes %s\n%s_rodata_bytes %s\n' \
    "$core" "$3" "$core" "$4" "$core" "$5" >>"$file"
  printf '%s_static_ram_bytes %s\n%s_peak_stack_bytes %s\n' "$core" "$6" "$core" "$7" >>"$file"
}

cmd_lint() {
  setup
  local t f rc=0
  (cd "$ROOT" && cargo fmt -p picomis-firmware -p picomis-embedded -p picomis-softfloat -- --check) || rc=1
  for t in $M4 $M0 $RV; do
    (cd "$ROOT" && CARGO_TARGET_DIR="$TD" cargo clippy --quiet -p picomis-softfloat --target $t -- -D warnings) || rc=1
    for f in "" "--features defmt" "--features defmt,fixed"; do
      # shellcheck disable=SC2086
      (cd "$ROOT" && CARGO_TARGET_DIR="$TD" cargo clippy --quiet -p picomis-embedded --target $t $f -- -D warnings) || rc=1
    done
    for f in "" "--features rtt" "--no-default-features --features rtt" "--features measure" "--features softfloat-check" "--features fixed" "--features measure,fixed" "--features rtt,fixed"; do
      # shellcheck disable=SC2086
      (cd "$FW" && CARGO_TARGET_DIR="$TD" cargo clippy --quiet --profile firmware --target $t $f -- -D warnings) || rc=1
    done
  done
  return $rc
}

# The board examples: folder under boards/ and target.
BOARD_EXAMPLES=("stm32f4-st7789 $M4" "rp2040-ili9341 $M0")

# Each board example: rustfmt, clippy -D warnings and a release build (fat LTO, as a user flashes
# it) for its target, with its own Cargo.lock (--locked); prints the ELF's flash sections.
cmd_boards() {
  setup
  local b dir target elf start=$SECONDS
  for b in "${BOARD_EXAMPLES[@]}"; do
    read -r dir target <<<"$b"
    step "board example boards/$dir ($target)"
    elf="$TD/$target/release/picomis-$dir"
    if (cd "$ROOT/boards/$dir" && cargo fmt -- --check &&
        CARGO_TARGET_DIR="$TD" cargo clippy --locked --release --quiet -- -D warnings &&
        CARGO_TARGET_DIR="$TD" cargo build --locked --release --quiet); then
      pass "boards/$dir: builds for $target, clippy -D warnings and rustfmt clean$(
        command -v arm-none-eabi-size >/dev/null && arm-none-eabi-size -A "$elf" |
          awk '$1==".text"{t=$2} $1==".rodata"{r=$2} END{printf " (text %d, rodata %d bytes)", t, r}')"
    else
      fail "boards/$dir: does not build for $target (or clippy, rustfmt)"
    fi
  done
  say "board examples took $((SECONDS - start)) s"
  say "boards: $PASSED passed, $FAILED failed"
  [ "$FAILED" -eq 0 ]
}

case "${1:-}" in
  setup) setup binutils ;;
  test) cmd_test ;;
  boards) cmd_boards ;;
  measure) cmd_measure ;;
  budget) cmd_measure check ;;
  lint) cmd_lint ;;
  *)
    sed -n '2,25p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
    ;;
esac
