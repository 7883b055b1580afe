"""`hsid.solve_many`: a simulated fleet's checkpoints (written by `hsid fleet simulate`, the
core's identifier as the firmware runs it) solve to the models `hsid.solve_checkpoint` and
`hsid fleet` give one by one; a damaged checkpoint costs its device only."""

import json
import subprocess

import pytest
from fleet_fixture import fleet  # noqa: F401 (a fixture)

import hsid


def test_solve_many_equals_the_serial_solve_and_the_cli(cli, fleet, tmp_path):
    states, names = fleet
    blobs = [(states / n).read_bytes() for n in names]
    many = hsid.solve_many(blobs, threads=2)
    assert len(many) == len(blobs)
    out = tmp_path / "models.jsonl"
    subprocess.run([cli, "fleet", "--states", states, "--out", out, "--threads", "1"],
                   check=True, capture_output=True)
    lines = [json.loads(line) for line in out.read_text().splitlines()]
    assert [line["device"] for line in lines] == names
    for blob, got, line in zip(blobs, many, lines):
        try:
            serial = hsid.solve_checkpoint(blob)
        except hsid.HsidError as e:
            assert isinstance(got, hsid.HsidError) and got.kind == e.kind
            assert line["error"]["message"] == str(e)
            continue
        assert isinstance(got, hsid.Model)
        assert json.loads(got.to_json()) == json.loads(serial.to_json())
        assert json.loads(got.to_json()) == line["model"]


def test_damaged_checkpoints_cost_their_device_only(fleet):
    states, names = fleet
    good = (states / names[0]).read_bytes()
    flipped = bytearray(good)
    flipped[len(good) // 2] ^= 0x40
    batch = [good, good[: len(good) // 2], bytes(flipped), b"HSID fw log\n", good]
    got = hsid.solve_many(batch)
    assert isinstance(got[0], hsid.Model) and isinstance(got[4], hsid.Model)
    kinds = [g.kind for g in got[1:4]]
    assert kinds == ["checkpoint_truncated", "checkpoint_checksum", "not_a_checkpoint"]
    assert all(isinstance(g, hsid.DataError) for g in got[1:4])
    assert json.loads(got[0].to_json()) == json.loads(got[4].to_json())


def test_zero_threads_is_refused(fleet):
    with pytest.raises(hsid.SettingsError, match="at least one thread"):
        hsid.solve_many([], threads=0)


def test_an_empty_batch_gives_an_empty_list():
    assert hsid.solve_many([]) == []
