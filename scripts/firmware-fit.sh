#!/usr/bin/env bash
# Which identification configurations fit which RAM class, per target: builds the firmware
# (examples/firmware) for each configuration (segments per path, f, p; j = 4000 columns, f32,
# plain sums) through HSID_FW_SEGMENTS / HSID_FW_F / HSID_FW_P, measures it with
# scripts/firmware-measure.sh under QEMU (-icount shift=0) and prints a markdown table:
#   RAM = static RAM (.data + .bss + .uninit) + painted peak stack, the whole identification on
#   the target (accumulation and the structured solve, the firmware's default), against 32 / 64 /
#   128 / 192 KiB, and the solve's instructions;
#   "host solve" = the RAM of the route that accumulates on the target and exports the state
#   for `hsid solve --state` on the host: static RAM without the solve workspace, plus the
#   checkpoint buffer (when it was the idle workspace), plus the accumulation's stack peak
#   (derived from the same run, not a separate build), and the smallest class it fits.
#
# Usage: scripts/firmware-fit.sh [--target TRIPLE]... [--config SEGMENTS,F,P]...
#   default targets: thumbv7em-none-eabihf riscv32imafc-unknown-none-elf
#   default configurations: 3,5,5 4,6,6 5,8,8 7,8,8 7,10,10 10,10,10
# Needs what scripts/firmware-measure.sh needs, for every target. Each configuration is a
# release build with LTO: about half a minute to two minutes each.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
TARGETS=()
CONFIGS=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --target) TARGETS+=("$2"); shift 2 ;;
    --config) CONFIGS+=("$2"); shift 2 ;;
    -h|--help) sed -n '2,20p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "firmware-fit: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[[ ${#TARGETS[@]} -gt 0 ]] || TARGETS=(thumbv7em-none-eabihf riscv32imafc-unknown-none-elf)
[[ ${#CONFIGS[@]} -gt 0 ]] || CONFIGS=(3,5,5 4,6,6 5,8,8 7,8,8 7,10,10 10,10,10)

die() { echo "firmware-fit: $*" >&2; exit 1; }
for c in "${CONFIGS[@]}"; do
  [[ "$c" =~ ^[0-9]+,[0-9]+,[0-9]+$ ]] \
    || die "configuration '$c' is not SEGMENTS,F,P (three decimal numbers, e.g. 7,10,10)"
done

TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT

num() { echo "$1" | sed -e ':a' -e 's/\([0-9]\)\([0-9]\{3\}\)\($\|,\)/\1,\2\3/' -e 'ta'; }
kib() { awk -v b="$1" 'BEGIN { printf "%.1f", b / 1024 }'; }
fits() { (( $1 <= $2 * 1024 )) && echo "✓" || echo "✗"; }
smallest() { # bytes -> the smallest class that holds them
  for k in 32 64 128 192; do (( $1 <= k * 1024 )) && { echo "$k KiB"; return; }; done
  echo "> 192 KiB"
}

echo "| target | segments per path | f | p | RAM (KiB) | 32 KiB | 64 KiB | 128 KiB | 192 KiB | solve instructions | host solve: RAM (KiB), fits |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for target in "${TARGETS[@]}"; do
  for c in "${CONFIGS[@]}"; do
    IFS=, read -r seg f p <<<"$c"
    echo "firmware-fit: $target, $seg segments per path, f = $f, p = $p" >&2
    sum="$TMP/summary"
    rm -f "$sum"
    HSID_FW_SEGMENTS="$seg" HSID_FW_F="$f" HSID_FW_P="$p" \
      "$ROOT/scripts/firmware-measure.sh" --target "$target" --summary "$sum" >/dev/null \
      || [[ -f "$sum" ]] || die "$target $c: the firmware did not build or run (see above)"
    declare -A V=()
    while IFS='=' read -r k v; do V["$k"]="$v"; done <"$sum"
    [[ "${V[segments]}/${V[f]}/${V[p]}" == "$seg/$f/$p" ]] \
      || die "$target $c: the firmware reports ${V[segments]}/${V[f]}/${V[p]}"
    ram="${V[ram_total]}"
    [[ "$ram" =~ ^[0-9]+$ ]] || die "$target $c: no peak stack measured"
    host=$(( V[static_ram] - V[workspace_bytes] + V[stack_peak_accumulation] ))
    [[ "${V[checkpoint_buffer]}" == workspace ]] && host=$(( host + V[checkpoint_bytes] ))
    short="${target%%-*}"
    solve="$(num "${V[solve_instr]}")"
    # A solve that failed (e.g. too few segments for the border) is said so, with its cost.
    if [[ "${V[solve]}" != ok ]]; then
      why="${V[solve]#fail fail }"; why="${why#solve: }"; why="${why%%: *}"
      solve="$solve (solve failed: $why)"
    fi
    echo "| $short | $seg | $f | $p | $(kib "$ram") | $(fits "$ram" 32) | $(fits "$ram" 64) | $(fits "$ram" 128) | $(fits "$ram" 192) | $solve | $(kib "$host"), $(smallest "$host") |"
    unset V
  done
done
echo
echo "Measured by \`scripts/firmware-fit.sh\` (each row a release build measured by \`scripts/firmware-measure.sh\` under QEMU \`-icount shift=0\`; j = 4000 columns, f32, plain sums)."
