"""The Python and Dask numbers of scripts/fleet-numbers.sh: solve_many, solve_checkpoint one by
one and a Dask LocalCluster of two worker processes on a directory of checkpoints."""

import pathlib
import sys
import time

import distributed

import hsid

sys.path.insert(0, "python/examples")
import dask_fleet  # noqa: E402


def main():
    states = pathlib.Path(sys.argv[1])
    blobs = [p.read_bytes() for p in sorted(states.iterdir())]
    n = len(blobs)
    t = time.perf_counter()
    hsid.solve_many(blobs, threads=1)
    many = time.perf_counter() - t
    t = time.perf_counter()
    for b in blobs:
        try:
            hsid.solve_checkpoint(b)
        except hsid.HsidError:
            pass
    single = time.perf_counter() - t
    print(f"python solve_many, 1 thread: {n / many:.1f} checkpoints/s ({1e3 * many / n:.2f} ms each)")
    print(f"python solve_checkpoint one by one: {n / single:.1f} checkpoints/s ({1e3 * single / n:.2f} ms each)")
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        dask_fleet.solve_on(client, blobs[:8], partitions=2)  # warm the workers
        t = time.perf_counter()
        dask_fleet.solve_on(client, blobs, partitions=8)
        d = time.perf_counter() - t
    print(f"dask LocalCluster, 2 worker processes: {n / d:.1f} checkpoints/s")


if __name__ == "__main__":
    main()
