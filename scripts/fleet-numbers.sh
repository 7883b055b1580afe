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
"$py" - "$work/states" <<'PY'
import pathlib, sys, time
import hsid
sys.path.insert(0, "python/examples")
import dask_fleet
states = pathlib.Path(sys.argv[1])
blobs = [p.read_bytes() for p in sorted(states.iterdir())]
n = len(blobs)
t = time.perf_counter(); hsid.solve_many(blobs, threads=1); many = time.perf_counter() - t
t = time.perf_counter()
for b in blobs:
    try:
        hsid.solve_checkpoint(b)
    except hsid.HsidError:
        pass
single = time.perf_counter() - t
print(f"python solve_many, 1 thread: {n / many:.1f} checkpoints/s ({1e3 * many / n:.2f} ms each)")
print(f"python solve_checkpoint one by one: {n / single:.1f} checkpoints/s ({1e3 * single / n:.2f} ms each)")
import distributed
with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                              dashboard_address=None) as cluster, distributed.Client(cluster) as client:
    dask_fleet.solve_on(client, blobs[:8], partitions=2)  # warm the workers
    t = time.perf_counter(); dask_fleet.solve_on(client, blobs, partitions=8); d = time.perf_counter() - t
print(f"dask LocalCluster, 2 worker processes: {n / d:.1f} checkpoints/s")
PY
