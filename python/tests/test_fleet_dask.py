"""The fleet across machines: `hsid.solve_many` mapped over partitions of checkpoint bytes on a
Dask `distributed.LocalCluster` with two worker processes gives the serial solve's models."""

import json

import pytest

import hsid

distributed = pytest.importorskip(
    "distributed", reason="dask[distributed] is not installed: pip install 'dask[distributed]'"
)

import pathlib  # noqa: E402
import sys  # noqa: E402

from fleet_fixture import fleet  # noqa: E402,F401 (a fixture)

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "examples"))
import dask_fleet  # noqa: E402


def test_a_local_cluster_of_two_processes_gives_the_serial_models(fleet):
    states, names = fleet
    blobs = [(states / n).read_bytes() for n in names]
    with distributed.LocalCluster(
        n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        got = dask_fleet.solve_on(client, blobs, partitions=4)
        workers = dask_fleet.workers_used(client)
    assert workers == 2
    assert len(got) == len(blobs)
    for blob, g in zip(blobs, got):
        try:
            serial = json.loads(hsid.solve_checkpoint(blob).to_json())
        except hsid.HsidError as e:
            assert g == {"error": {"kind": e.kind, "message": str(e)}}
            continue
        assert g == {"model": serial}


def test_a_plain_client_map_of_solve_checkpoint_returns_equal_models(fleet):
    """Models travel between processes by pickle: `client.map(hsid.solve_checkpoint, blobs)`
    gathers models equal to the serial ones."""
    states, names = fleet
    blobs, serial = [], []
    for n in names:
        blob = (states / n).read_bytes()
        try:
            serial.append(hsid.solve_checkpoint(blob))
        except hsid.HsidError:
            continue
        blobs.append(blob)
    assert len(blobs) >= 10
    with distributed.LocalCluster(
        n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        got = client.gather(client.map(hsid.solve_checkpoint, blobs, pure=False))
    assert got == serial
    assert all(isinstance(m, hsid.Model) for m in got)
