#!/usr/bin/env bash
# The Python call's overhead (docs/fleet.md): `hsid.solve_checkpoint` against the library call
# it wraps, on the same checkpoint bytes in memory, one thread each, ROUNDS rounds of REPS
# passes. Checkpoints from STATES (a directory), or DEVICES×WEEKS of the standard simulated
# fleet (default 100×4). Needs the virtual environment scripts/python-check.sh makes.
#
#   scripts/python-overhead.sh [STATES] [ROUNDS] [REPS]
set -euo pipefail
cd "$(dirname "$0")/.."
py=target/py-venv/bin/python
if [ ! -x "$py" ]; then
  echo "no target/py-venv: run scripts/python-check.sh first" >&2
  exit 1
fi
cargo build --release --quiet -p hsid-host --bin hsid --example checkpoint_solve_time
states=${1:-}
if [ -z "$states" ]; then
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  states=$work/states
  target/release/hsid fleet simulate --devices "${DEVICES:-100}" --weeks "${WEEKS:-4}" \
    --out "$states" --truth "$work/truth.csv" >/dev/null
fi
"$py" scripts/python_overhead.py "$states" target/release/examples/checkpoint_solve_time \
  "${2:-5}" "${3:-3}"
