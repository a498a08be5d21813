#!/usr/bin/env bash
# No f64 and no allocator in BUILT objects (the source grep in scripts/test.sh is only a fast first
# check: it cannot see `1.0f64` in an expression it does not match, nor dependencies).
#
#   scripts/symbols.sh FILE...      fails if a file (ELF, object or rlib/staticlib archive) defines
#                                   or references a double-precision soft-float routine
#                                   (__aeabi_dadd, __aeabi_f2d, __adddf3, __extendsfdf2, ...: any
#                                   `df` routine) or an allocator symbol (__rust_alloc,
#                                   __rg_alloc, __rdl_alloc, ...)
#   scripts/symbols.sh --self-test  the check finds both kinds in objects that have them (the
#                                   target's compiler_builtins and alloc rlibs), so it can fail
#   scripts/symbols.sh --strategies none FILE...
#                                   fails if a linked firmware carries code of a strategy beyond
#                                   the lecture's: selection by contribution (contribution), a
#                                   sample of every light (every), lobe mixing (lobe), the
#                                   one-sample model (one-sample), the control variate
#                                   (control-variate)
#   scripts/symbols.sh --strategies LIST FILE...
#                                   LIST: names from those, comma-separated; fails unless the
#                                   firmware carries the code of exactly those
#
# On a Cortex-M4F (single-precision FPU) and a Cortex-M0 (no FPU) every f64 operation is a call to
# such a routine, so their absence from the linked firmware means no f64 arithmetic ran. On x86
# f64 is native and leaves no symbol: the check is for the thumb builds.
# Tool: llvm-nm of the Rust toolchain (rustup component llvm-tools, added here if missing), else
# arm-none-eabi-nm (Debian binutils-arm-none-eabi).
set -uo pipefail

F64='__aeabi_(d[a-z0-9]+|[a-z0-9]+2d[a-z]*)$|(^|[0-9])__[a-z]*df[a-z]*[0-9]?$'
ALLOC='__(rust|rg|rdl)_(alloc|dealloc|realloc|alloc_zeroed|alloc_error_handler)($|[^a-z_])|__rust_no_alloc_shim'

# The toolchain's own llvm-nm (rustup component llvm-tools: it reads the LLVM bitcode that the
# standard library's rlibs carry), else arm-none-eabi-nm.
nm_tool() {
  local t
  t="$(rustc --print sysroot)/lib/rustlib/$(rustc -vV | sed -n 's/^host: //p')/bin/llvm-nm"
  if [ ! -x "$t" ]; then
    rustup component add llvm-tools >/dev/null 2>&1 || true
  fi
  [ -x "$t" ] && { echo "$t"; return 0; }
  command -v arm-none-eabi-nm >/dev/null && { echo arm-none-eabi-nm; return 0; }
  echo "symbols.sh: no llvm-nm (rustup component add llvm-tools) or arm-none-eabi-nm" >&2
  return 1
}

# Symbol names (defined and undefined) of FILE, one per line.
names() {
  "$NM" --no-sort "$1" 2>/dev/null | awk 'NF >= 2 {print $NF}'
}

# check FILE: prints the offending symbols; returns 1 if there are any.
check() {
  local file=$1 syms bad_f64 bad_alloc
  [ -f "$file" ] || { echo "symbols.sh: $file: no such file" >&2; return 1; }
  syms=$(names "$file")
  if [ -z "$syms" ]; then
    echo "symbols.sh: $file: no symbols read (wrong file or tool?)" >&2
    return 1
  fi
  bad_f64=$(grep -E "$F64" <<<"$syms" | sort -u)
  bad_alloc=$(grep -E "$ALLOC" <<<"$syms" | sort -u)
  if [ -n "$bad_f64$bad_alloc" ]; then
    [ -n "$bad_f64" ] && sed "s|^|$file: f64 routine: |" <<<"$bad_f64"
    [ -n "$bad_alloc" ] && sed "s|^|$file: allocator: |" <<<"$bad_alloc"
    return 1
  fi
  echo "ok (no f64, no alloc; $(wc -l <<<"$syms") symbols): $file"
}

# The strategies beyond the lecture's, as "name:pattern" (a pattern of demangled symbol names
# that the strategy's code keeps out of line: the kernel marks them #[inline(never)]).
STRATEGIES="contribution:select::contribution::ByContribution every:::every_light_sample lobe:light::lobe::Lobe::towards one-sample:estimate_direct_one_sample control-variate:closed_form::unoccluded_light"

# strategies WANT FILE: WANT none (no strategy's code) or a comma-separated list of the names of
# STRATEGIES (exactly those strategies' code).
strategies() {
  local want=$1 file=$2 syms s name pattern found wanted rc=0
  [ -f "$file" ] || { echo "symbols.sh: $file: no such file" >&2; return 1; }
  syms=$("$NM" -C --no-sort "$file" 2>/dev/null)
  [ -n "$syms" ] || { echo "symbols.sh: $file: no symbols read" >&2; return 1; }
  for s in $STRATEGIES; do
    name=${s%%:*}
    pattern=${s#*:}
    found=$(grep -cF "$pattern" <<<"$syms")
    wanted=0
    [[ ",$want," == *",$name,"* ]] && wanted=1
    if [ $wanted = 0 ] && [ "$found" -gt 0 ]; then
      echo "$file: carries $name code ($(grep -F "$pattern" <<<"$syms" | head -n1 | awk '{print $NF}'))"
      rc=1
    elif [ $wanted = 1 ] && [ "$found" -eq 0 ]; then
      echo "$file: carries no $name code (no symbol matching $pattern)"
      rc=1
    fi
  done
  [ $rc = 0 ] && echo "ok (code of the strategies beyond the lecture's: $want): $file"
  return $rc
}

self_test() {
  local sysroot lib rc=0
  sysroot=$(rustc --print sysroot)
  for lib in compiler_builtins alloc; do
    local f
    f=$(ls "$sysroot"/lib/rustlib/thumbv7em-none-eabihf/lib/lib"$lib"-*.rlib 2>/dev/null | head -n1)
    if [ -z "$f" ]; then
      echo "symbols.sh --self-test: no $lib rlib for thumbv7em-none-eabihf" >&2
      rc=1
    elif check "$f" >/dev/null; then
      echo "symbols.sh --self-test: the check passed $f, which has f64 routines / allocator calls" >&2
      rc=1
    else
      echo "self-test: $lib rlib is rejected, as it must be"
    fi
  done
  return $rc
}

NM=$(nm_tool) || exit 1
if [ "${1:-}" = --self-test ]; then
  self_test
  exit
fi
if [ "${1:-}" = --strategies ]; then
  want=${2:-}
  for name in ${want//,/ }; do
    [ "$name" = none ] || [[ " $STRATEGIES" == *" $name:"* ]] ||
      { echo "symbols.sh --strategies none|NAME,NAME... FILE... (names: contribution, every, lobe, one-sample, control-variate)" >&2; exit 2; }
  done
  shift 2
  rc=0
  for f in "$@"; do
    strategies "$want" "$f" || rc=1
  done
  exit $rc
fi
[ $# -gt 0 ] || { sed -n '2,24p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
rc=0
for f in "$@"; do
  check "$f" || rc=1
done
exit $rc
