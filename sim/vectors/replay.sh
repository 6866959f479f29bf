#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Replay a committed vector set through its unit's plain Verilog bench, no Python involved.
#
#   sim/vectors/replay.sh <set> [icarus|verilator|both]     (default: icarus)
#
# <set> is a folder name under sim/vectors/ (e.g. divider_default) or a path to a set folder.
# Builds sim/vectors/tb_<unit>.v with rtl/<unit>.f's files and the set's parameters (params.txt; ROM
# images from rtl/rom, absolute paths, and -DSHADING_ROM_DIR; VECTOR_FILE = the set's
# vectors.bin) under Icarus (iverilog -g2005, vvp) or Verilator (--binary -O3), and runs it:
# one instance of the unit with RESET_ALL = 0 and one with RESET_ALL = 1, each against its own
# expected outputs (the file carries both predictions).  Prints the bench's MISMATCH lines and
# its PASS or FAIL line; exits non-zero on any mismatch or build error.
# REPLAY_BUILD=<dir> builds there (kept; default: a temporary folder, removed).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
rtl=$(cd "$here/../../rtl" && pwd)

usage() { echo "usage: $0 <set> [icarus|verilator|both]" >&2; exit 2; }
[ $# -ge 1 ] && [ $# -le 2 ] || usage
if [ -d "$1" ]; then setdir=$(cd "$1" && pwd); else setdir="$here/$1"; fi
tool=${2:-icarus}
case "$tool" in icarus|verilator|both) ;; *) usage ;; esac
[ -f "$setdir/params.txt" ] || { echo "error: no vector set at $setdir (params.txt missing)" >&2; exit 2; }

unit=""
names=()
values=()
while read -r name value; do
  case "$name" in ''|'#'*) continue ;; UNIT) unit=$value; continue ;; esac
  # a "rom/..." image path is relative to rtl/
  case "$value" in '"rom/'*) value="\"$rtl/${value#\"}" ;; esac
  names+=("$name")
  values+=("$value")
done < "$setdir/params.txt"
[ -n "$unit" ] || { echo "error: $setdir/params.txt names no UNIT" >&2; exit 2; }
top="tb_$unit"
[ -f "$setdir/vectors.bin" ] || { echo "error: no vector file $setdir/vectors.bin" >&2; exit 2; }
names+=(VECTOR_FILE)
values+=("\"$setdir/vectors.bin\"")
# the unit's sources: the files rtl/<unit>.f lists (one a line, relative to rtl/; // comments)
[ -f "$rtl/$unit.f" ] || { echo "error: no source list $rtl/$unit.f" >&2; exit 2; }
sources=("$here/$top.v")
while read -r line; do
  line=${line%%//*}
  line=${line//[[:space:]]/}
  [ -n "$line" ] && sources+=("$rtl/$line")
done < "$rtl/$unit.f"
define="SHADING_ROM_DIR=\"$rtl/rom\""

if [ -n "${REPLAY_BUILD:-}" ]; then
  build=$REPLAY_BUILD
  mkdir -p "$build"
else
  build=$(mktemp -d)
  trap 'rm -rf "$build"' EXIT
fi

run_icarus() {
  local args=()
  for i in "${!names[@]}"; do args+=("-P$top.${names[$i]}=${values[$i]}"); done
  echo "== $(basename "$setdir"): $top under Icarus"
  iverilog -g2005 -o "$build/$top.vvp" -s "$top" -I "$here" "-D$define" "${args[@]}" "${sources[@]}"
  vvp -n "$build/$top.vvp"
}

run_verilator() {
  local args=()
  for i in "${!names[@]}"; do args+=("-G${names[$i]}=${values[$i]}"); done
  echo "== $(basename "$setdir"): $top under Verilator"
  verilator --binary -j 2 -O3 --x-assign fast --x-initial fast -Wno-fatal -Wno-lint -Wno-style \
    --top-module "$top" -Mdir "$build/obj_$top" \
    -I"$here" "-D$define" "${args[@]}" "${sources[@]}" > "$build/verilator_build.log" 2>&1 \
    || { cat "$build/verilator_build.log" >&2; echo "FAIL: verilator could not build $top" >&2; exit 1; }
  "$build/obj_$top/V$top"
}

case "$tool" in
  icarus) run_icarus ;;
  verilator) run_verilator ;;
  both) run_icarus; run_verilator ;;
esac
