"""The Python call against the Rust call on the same checkpoint bytes in memory: ROUNDS rounds,
each running the library's loop (examples/checkpoint_solve_time, REPS passes over every
checkpoint) and then `hsid.solve_checkpoint` over the same bytes (REPS passes), one thread each.
Prints the time per call of both (median and range over all passes), the median of the
per-round ratios and the load average. Called by scripts/python-overhead.sh."""

import json
import os
import pathlib
import statistics
import subprocess
import sys
import time

import hsid


def python_passes(blobs, reps):
    """Mean ms per `hsid.solve_checkpoint` call, one value per pass over `blobs`."""
    out = []
    for _ in range(reps):
        start = time.perf_counter()
        for b in blobs:
            try:
                hsid.solve_checkpoint(b)
            except hsid.HsidError:
                pass
        out.append(1e3 * (time.perf_counter() - start) / len(blobs))
    return out


def rust_passes(binary, states, reps):
    """The same from the library call, in its own process."""
    run = subprocess.run([binary, str(states), str(reps)], check=True, capture_output=True, text=True)
    return json.loads(run.stdout)


def summary(name, v):
    return (f"{name}: {statistics.median(v):.4f} ms per call "
            f"(median of {len(v)} passes; range {min(v):.4f} to {max(v):.4f})")


def main():
    states, binary = pathlib.Path(sys.argv[1]), sys.argv[2]
    rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    reps = int(sys.argv[4]) if len(sys.argv) > 4 else 3
    blobs = [p.read_bytes() for p in sorted(states.iterdir())]
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    python_passes(blobs, 1)  # warm: the module, the allocator
    rust, py, ratios = [], [], []
    for _ in range(rounds):
        r = rust_passes(binary, states, reps)
        p = python_passes(blobs, reps)
        rust += r["per_call_ms"]
        py += p
        ratios.append(statistics.median(p) / statistics.median(r["per_call_ms"]))
    print(f"{len(blobs)} checkpoints ({r['failed']} fail in both), {rounds} rounds of {reps} passes, one thread")
    print(summary("rust  hsid_host::identify::solve_checkpoint + to_json", rust))
    print(summary("python hsid.solve_checkpoint", py))
    over = statistics.median(ratios) - 1
    print(f"python overhead: {100 * over:+.1f} % (median of the per-round ratios; "
          f"rounds from {100 * (min(ratios) - 1):+.1f} % to {100 * (max(ratios) - 1):+.1f} %)")
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
