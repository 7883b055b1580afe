#!/usr/bin/env bash
# The fleet's numbers (docs/fleet.md): checkpoint solve time on one core, throughput on 1 and 2
# threads, the Python call against the Rust call on the same checkpoints, and the Dask
# LocalCluster's throughput (the last two need the virtual environment scripts/python-check.sh
# makes). DEVICES×WEEKS checkpoints of the standard simulated fleet (default 100×4).
set -euo pipefail
cd "$(dirname "$0")/.."
devices=${DEVICES:-100}
weeks=${WEEKS:-4}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cargo build --release --quiet -p hsid-host --bin hsid
hsid=target/release/hsid
$hsid fleet simulate --devices "$devices" --weeks "$weeks" --out "$work/states" --truth "$work/truth.csv"
for t in 1 2; do
  echo "threads $t: $($hsid fleet --states "$work/states" --out "$work/models-$t.jsonl" --threads "$t")"
done
cmp "$work/models-1.jsonl" "$work/models-2.jsonl" && echo "1 and 2 threads: identical models"
py=target/py-venv/bin/python
if [ ! -x "$py" ]; then
  echo "no target/py-venv: run scripts/python-check.sh for the Python and Dask numbers" >&2
  exit 0
fi
"$py" scripts/fleet_numbers.py "$work/states"
