#!/usr/bin/env bash
# Measures the onboard-identification firmware (examples/firmware) in release, for one target:
#   flash (the load image: .text + .rodata + .data, plus .vector_table on the Cortex-M4 and
#   .init.rust + .eh_frame on RISC-V), static RAM (.data + .bss + .uninit), peak stack (stack
#   painting, reported by the firmware), and instruction counts per sample update and for the
#   final solve (under QEMU `-icount shift=0`: SysTick on the Cortex-M4, one tick = 40
#   instructions; `minstret` on RISC-V, one tick = 1 instruction; reported by the firmware on its
#   `HSID cost ...` line), and the checkpoint the firmware exports (`HSID state ...`: its size
#   and the cost of saving it).
# Prints a markdown table on stdout. Exits non-zero if the build or the firmware fails, and with
# --enforce also when a budget of the table's third column is exceeded (flash ≤ 128 KiB, RAM total
# ≤ 64 KiB with the structured solve (the default; ≤ 192 KiB with the `dense-solve` feature), the
# mean per-sample update ≤ 2,000 instructions, the final solve ≤ 30 M instructions).
# QEMU runs in a scratch folder, where the firmware writes its checkpoint `hsid-state.bin`;
# `--state FILE` keeps a copy (solve it with `hsid solve --state FILE`).
#
# Usage: scripts/firmware-measure.sh [--target TRIPLE] [--log FILE] [--state FILE]
#                                    [--summary FILE] [--enforce] [-- EXTRA CARGO BUILD ARGS...]
#   --target thumbv7em-none-eabihf (default; QEMU mps2-an386, Cortex-M4) or
#            riscv32imafc-unknown-none-elf (QEMU virt, RV32IMAFC)
#   --summary FILE  also writes the measured numbers as key=value lines (scripts/firmware-fit.sh)
#   e.g. scripts/firmware-measure.sh -- --features defmt   (the defmt variant, Cortex-M4 only;
#        needs defmt-print)
# Needs: cargo with the target (added with rustup if missing), QEMU (Debian: qemu-system-arm,
#        or qemu-system-misc for qemu-system-riscv32), a size tool (arm-none-eabi-size from
#        binutils-arm-none-eabi, llvm-size or binutils' size), and for a defmt build
#        defmt-print (cargo install defmt-print).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
FW="$ROOT/examples/firmware"
TARGET=thumbv7em-none-eabihf
LOG=""
STATE=""
SUMMARY=""
ENFORCE=0
EXTRA=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --target) TARGET="$2"; shift 2 ;;
    --log) LOG="$2"; shift 2 ;;
    --state) STATE="$2"; shift 2 ;;
    --summary) SUMMARY="$2"; shift 2 ;;
    --enforce) ENFORCE=1; shift ;;
    --) shift; EXTRA=("$@"); break ;;
    -h|--help) sed -n '2,25p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "firmware-measure: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done

die() { echo "firmware-measure: $*" >&2; exit 1; }

# Per target: QEMU and its arguments, the board's name, the counter, the sections of the flash
# image besides .text + .rodata + .data.
case "$TARGET" in
  thumbv7em-none-eabihf)
    QEMU=qemu-system-arm; QEMU_PKG=qemu-system-arm
    QEMU_ARGS=(-machine mps2-an386 -cpu cortex-m4)
    BOARD="mps2-an386 (Cortex-M4)"; COUNTER="SysTick tick"
    FLASH_EXTRA=(.vector_table) ;;
  riscv32imafc-unknown-none-elf)
    QEMU=qemu-system-riscv32; QEMU_PKG=qemu-system-misc
    QEMU_ARGS=(-machine virt -bios none)
    BOARD="virt (RV32IMAFC, machine mode)"; COUNTER="\`minstret\` tick"
    FLASH_EXTRA=(.init.rust .eh_frame) ;;
  *) die "unknown target '$TARGET' (thumbv7em-none-eabihf or riscv32imafc-unknown-none-elf)" ;;
esac
ELF="$FW/target/$TARGET/release/hsid-firmware"

command -v cargo >/dev/null || die "cargo not found"
if command -v rustup >/dev/null && ! rustup target list --installed | grep -qx "$TARGET"; then
  rustup target add "$TARGET" >&2
fi
command -v "$QEMU" >/dev/null \
  || die "$QEMU not found (Debian: apt-get install -y $QEMU_PKG)"
if [[ "$TARGET" == thumb* ]] && command -v arm-none-eabi-size >/dev/null; then SIZE=arm-none-eabi-size
elif command -v llvm-size >/dev/null; then SIZE=llvm-size
elif command -v size >/dev/null; then SIZE=size
else die "no size tool (Debian: apt-get install -y binutils-arm-none-eabi)"; fi

echo "firmware-measure: building $FW (release, $TARGET)" >&2
(cd "$FW" && cargo build --release --target "$TARGET" "${EXTRA[@]}" >&2)
[[ -f "$ELF" ]] || die "no ELF at $ELF"

# Section sizes (SysV format: name size addr).
declare -A SEC=()
while read -r name size _; do
  [[ "$name" == .* && "$size" =~ ^[0-9]+$ ]] && SEC["$name"]=$size
done < <("$SIZE" -A "$ELF")
sec() { echo "${SEC[$1]:-0}"; }
FLASH=$(( $(sec .text) + $(sec .rodata) + $(sec .data) ))
for s in "${FLASH_EXTRA[@]}"; do FLASH=$(( FLASH + $(sec "$s") )); done
FLASH_PARTS="$(printf ' + %s' "${FLASH_EXTRA[@]}" .text .rodata .data)"
FLASH_PARTS="${FLASH_PARTS# + }"
STATIC_RAM=$(( $(sec .data) + $(sec .bss) + $(sec .uninit) ))

echo "firmware-measure: running under $QEMU $BOARD with -icount shift=0" >&2
OUT="$(mktemp)"
RUNDIR="$(mktemp -d)"
trap 'rm -f "$OUT"; rm -rf "$RUNDIR"' EXIT
set +e
# In a scratch folder: semihosting writes the firmware's hsid-state.bin relative to QEMU's cwd.
(cd "$RUNDIR" && timeout 900 "$QEMU" "${QEMU_ARGS[@]}" \
  -semihosting-config enable=on,target=native -nographic -monitor none -serial none \
  -icount shift=0 -kernel "$ELF") >"$OUT" 2>&1
STATUS=$?
set -e
# A defmt build (it has a .defmt section) prints binary defmt frames: decode them.
if [[ -n "${SEC[.defmt]:-}" ]]; then
  command -v defmt-print >/dev/null || die "defmt build: defmt-print not found (cargo install defmt-print)"
  DECODED="$(mktemp)"
  defmt-print -e "$ELF" --log-format '{s}' <"$OUT" >"$DECODED" 2>&1 || true
  mv "$DECODED" "$OUT"
fi
[[ -n "$LOG" ]] && cp "$OUT" "$LOG"
FAILED="$(grep -m1 -E '^HSID (fail|panic)' "$OUT" || true)"
if [[ $STATUS -ne 0 ]]; then
  [[ -n "$FAILED" ]] && echo "$FAILED" >&2 || tail -n 20 "$OUT" >&2
  # With --summary, a run whose solve failed after the costs were printed still writes its
  # numbers (solve=fail) before this script fails.
  [[ -n "$SUMMARY" ]] && grep -q '^HSID cost ' "$OUT" || die "firmware exited with status $STATUS"
fi

if [[ -n "$STATE" && $STATUS -eq 0 ]]; then
  [[ -f "$RUNDIR/hsid-state.bin" ]] || die "the firmware wrote no hsid-state.bin"
  cp "$RUNDIR/hsid-state.bin" "$STATE"
  echo "firmware-measure: checkpoint copied to $STATE (hsid solve --state $STATE)" >&2
fi
declare -A ST=()
STATE_LINE="$(grep -m1 '^HSID state ' "$OUT" || true)"
for kv in ${STATE_LINE#HSID state }; do ST["${kv%%=*}"]="${kv#*=}"; done

COST="$(grep -m1 '^HSID cost ' "$OUT" || true)"
[[ -n "$COST" ]] || die "no 'HSID cost' line in the firmware output"
declare -A K=()
for kv in ${COST#HSID cost }; do K["${kv%%=*}"]="${kv#*=}"; done
key() { echo "${K[$1]:-n/a}"; }

kib() { awk -v b="$1" 'BEGIN { printf "%.1f KiB", b / 1024 }'; }
num() { echo "$1" | sed -e ':a' -e 's/\([0-9]\)\([0-9]\{3\}\)\($\|,\)/\1,\2\3/' -e 'ta'; }
OVER=() # budgets exceeded, for --enforce
ok() { # value limit [name] -> ✓/✗ (n/a when the value is missing); a name makes it a budget
  [[ "$1" =~ ^[0-9]+$ ]] || { echo "n/a"; return; }
  if (( $1 <= $2 )); then echo "✓"; else echo "✗"; [[ -n "${3:-}" ]] && OVER+=("$3 $1 > $2"); fi
}

PEAK="$(key stack_peak_bytes)"
TOTAL_RAM="n/a"
[[ "$PEAK" =~ ^[0-9]+$ ]] && TOTAL_RAM=$(( STATIC_RAM + PEAK ))
PER_SAMPLE="$(key per_sample_instr)"
SOLVE="$(key solve_instr)"

if [[ -n "$SUMMARY" ]]; then
  CFG="$(grep -m1 '^HSID config ' "$OUT" || true)"
  declare -A C=()
  for kv in ${CFG#HSID config }; do C["${kv%%=*}"]="${kv#*=}"; done
  {
    echo "target=$TARGET"
    echo "segments=${C[segments]:-n/a}"
    echo "f=${C[f]:-n/a}"
    echo "p=${C[p]:-n/a}"
    echo "flash=$FLASH"
    echo "static_ram=$STATIC_RAM"
    echo "stack_peak=$PEAK"
    echo "ram_total=$TOTAL_RAM"
    echo "workspace_bytes=$(key workspace_bytes)"
    echo "identifier_bytes=$(key identifier_bytes)"
    echo "stack_peak_accumulation=$(key stack_peak_accumulation_bytes)"
    echo "checkpoint_bytes=${ST[bytes]:-n/a}"
    echo "checkpoint_buffer=${ST[buffer]:-n/a}"
    echo "per_sample_instr=$PER_SAMPLE"
    echo "solve_instr=$SOLVE"
    if [[ $STATUS -eq 0 ]]; then echo "solve=ok"; else echo "solve=fail ${FAILED#HSID }"; fi
  } >"$SUMMARY"
fi
[[ $STATUS -eq 0 ]] || die "firmware exited with status $STATUS"

echo "| quantity | value | budget |"
echo "| --- | --- | --- |"
ok "$FLASH" 131072 flash >/dev/null
echo "| flash ($FLASH_PARTS) | $(num "$FLASH") B ($(kib "$FLASH")) | ≤ 128 KiB $(ok "$FLASH" 131072) |"
echo "| static RAM (.data + .bss + .uninit) | $(num "$STATIC_RAM") B ($(kib "$STATIC_RAM")) | |"
if [[ "${K[workspace_bytes]+x}" ]]; then
  echo "| … of which solve workspace | $(num "$(key workspace_bytes)") B | |"
  echo "| … of which identifier (accumulated state) | $(num "$(key identifier_bytes)") B | |"
fi
echo "| peak stack (painted) | $(num "$PEAK") B ($(kib "${PEAK//[^0-9]/}")) | |"
if [[ "${K[stack_peak_solve_bytes]+x}" ]]; then
  echo "| … until the end of the accumulation | $(num "$(key stack_peak_accumulation_bytes)") B | |"
  echo "| … during the solve | $(num "$(key stack_peak_solve_bytes)") B | |"
fi
# The RAM budget of the firmware's solve (its config line says which): 64 KiB for the structured
# solve, 192 KiB for the dense one.
SOLVE_KIND="$(grep -m1 -o ' solve=[a-z]*' "$OUT" | cut -d= -f2 || true)"
if [[ "$SOLVE_KIND" == dense ]]; then RAM_LIMIT=196608; else RAM_LIMIT=65536; fi
if [[ "$TOTAL_RAM" != n/a ]]; then
  ok "$TOTAL_RAM" "$RAM_LIMIT" "RAM total" >/dev/null
  echo "| RAM total (static + peak stack) | $(num "$TOTAL_RAM") B ($(kib "$TOTAL_RAM")) | ≤ $(( RAM_LIMIT / 1024 )) KiB $(ok "$TOTAL_RAM" "$RAM_LIMIT") (${SOLVE_KIND:-?} solve) |"
fi
echo "| samples accumulated (after the hold) | $(num "$(key samples)") | |"
ok "$PER_SAMPLE" 2000 "instructions per sample (mean)" >/dev/null
echo "| instructions per sample update (push), mean | $(num "$PER_SAMPLE") | ≤ 2,000 $(ok "$PER_SAMPLE" 2000) |"
if [[ "${K[per_sample_max_instr]+x}" ]]; then
  echo "| instructions per sample update (push), max | $(num "$(key per_sample_max_instr)") | |"
fi
ok "$SOLVE" 30000000 "instructions for the final solve" >/dev/null
echo "| instructions for the final solve | $(num "$SOLVE") | ≤ 30,000,000 $(ok "$SOLVE" 30000000) |"
if [[ -n "${ST[bytes]:-}" ]]; then
  echo "| checkpoint exported to the host (\`hsid-state.bin\`) | $(num "${ST[bytes]}") B, crc ${ST[crc]:-?}, saved into $( [[ "${ST[buffer]:-}" == workspace ]] && echo "the idle solve workspace (no extra RAM)" || echo "a static buffer of its own" ) | |"
  echo "| instructions to save the checkpoint (\`Identifier::save\`) | $(num "${ST[save_instr]:-n/a}") | |"
fi
echo
echo "Measured by \`scripts/firmware-measure.sh --target $TARGET\`: QEMU $("$QEMU" --version | head -n1 | awk '{print $4}') $BOARD, \`-icount shift=0\`, 1 $COUNTER = $(key instr_per_tick) instruction$( [[ "$(key instr_per_tick)" == 1 ]] || echo s); sizes by \`$SIZE -A\`."
if [[ $ENFORCE -eq 1 && ${#OVER[@]} -gt 0 ]]; then
  die "budget exceeded on $TARGET: ${OVER[*]}"
fi
