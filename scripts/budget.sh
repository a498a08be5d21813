#!/usr/bin/env bash
# The firmware's figures: one committed file (firmware/budget.json), the table of docs/firmware.md
# generated from it, and a budget check. `scripts/firmware.sh measure` and `scripts/firmware.sh budget` call
# this; nothing else writes the file or the table.
#
#   scripts/budget.sh write FIGURES      FIGURES ("key value" lines, from firmware.sh) ->
#                                        firmware/budget.json
#   scripts/budget.sh readme             rewrites the table of docs/firmware.md between the markers
#   scripts/budget.sh readme --check     fails if that table differs from budget.json
#   scripts/budget.sh check FIGURES      fails if instructions per camera sample (f32 and
#                                        fixed-point builds, lecture and best settings), flash
#                                        text, static RAM or peak stack exceed budget.json by
#                                        > 2 %, or a figure within its stated target crosses it
#   scripts/budget.sh table              prints the generated table (what readme writes)
#
# The logic and its tests are Rust: `picomis-tools budget` (tools/src/budget/; the cores, keys,
# targets and the tolerance are in tools/src/budget/keys.rs). This script keeps the command line.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
case "${1:-}" in
  write | check)
    [ -n "${2:-}" ] || { echo "budget.sh: $1: which figures file?" >&2; exit 2; }
    # cargo runs from the workspace root (a folder's .cargo/config.toml, such as firmware's,
    # would choose another target): the figures file's path from here.
    [[ $2 == /* ]] || set -- "$1" "$PWD/$2" "${@:3}"
    ;;
  readme | table) ;;
  *)
    sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
    ;;
esac
cd "$ROOT"
exec cargo run -q --release -p picomis-tools -- --root "$ROOT" budget "$@"
