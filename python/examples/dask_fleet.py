"""A fleet's checkpoints solved across machines with Dask: the checkpoint bytes are split into
partitions, each partition is solved by ``hsid.solve_many`` on a worker (all the worker's cores),
and every device's outcome comes back as plain JSON (its model, or its error's kind and message).

    python dask_fleet.py STATES_DIR [SCHEDULER_ADDRESS]

Without a scheduler address it starts a ``LocalCluster`` of two worker processes on this machine.
"""

import json
import pathlib
import sys

import hsid


def solve_partition(blobs):
    """One partition on one worker: models as JSON, errors as their kind and message."""
    out = []
    for r in hsid.solve_many(blobs):
        if isinstance(r, hsid.Model):
            out.append({"model": json.loads(r.to_json())})
        else:
            out.append({"error": {"kind": r.kind, "message": str(r)}})
    return out


def solve_on(client, blobs, partitions):
    """Solves ``blobs`` (a list of checkpoint bytes) on ``client``'s cluster in ``partitions``
    partitions; returns one outcome per checkpoint, in order."""
    size = max(1, -(-len(blobs) // partitions))
    parts = [blobs[i : i + size] for i in range(0, len(blobs), size)]
    futures = client.map(solve_partition, parts, pure=False)
    return [r for part in client.gather(futures) for r in part]


def workers_used(client):
    """The number of worker processes of the cluster."""
    return len(client.scheduler_info()["workers"])


def main():
    import distributed

    states = pathlib.Path(sys.argv[1])
    names = sorted(p.name for p in states.iterdir() if p.is_file())
    blobs = [(states / n).read_bytes() for n in names]
    if len(sys.argv) > 2:
        client = distributed.Client(sys.argv[2])
    else:
        cluster = distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1)
        client = distributed.Client(cluster)
    with client:
        for name, r in zip(names, solve_on(client, blobs, partitions=4 * workers_used(client))):
            print(json.dumps({"device": name, **r}))


if __name__ == "__main__":
    main()
