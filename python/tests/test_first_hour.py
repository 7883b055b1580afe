"""The rough edges of a first hour: an excitation shorter than its hold, one bytes object given
to `solve_many`, `diagnose`'s sample time and units."""

import subprocess

import numpy as np
import pytest

import hsid


def test_an_excitation_no_longer_than_its_hold_is_refused_as_by_the_command_line(cli):
    with pytest.raises(hsid.SettingsError) as e:
        hsid.excite(-1.0, 1.0, 100)
    assert e.value.kind == "excitation_too_short"
    message = str(e.value)
    assert "100 samples are no more than the hold of 300" in message
    assert "give more samples than the hold" in message
    run = subprocess.run(
        [cli, "excite", "--umin", "-1", "--umax", "1", "--samples", "100"],
        capture_output=True, text=True,
    )
    assert run.returncode != 0 and run.stdout == ""
    assert message in run.stderr, run.stderr
    with pytest.raises(hsid.SettingsError) as e:
        hsid.excite(-1.0, 1.0, 300, hold=300)
    assert e.value.kind == "excitation_too_short"
    # One sample past the hold is a record: the hold at u_min, then one random level.
    u = hsid.excite(-1.0, 1.0, 301, hold=300)
    assert len(u) == 301 and np.all(u[:300] == -1.0)
    assert hsid.excite(-1.0, 1.0, 10, hold=0).shape == (10,)


def test_solve_many_refuses_one_bytes_object(checkpoint):
    for wrong in (checkpoint, bytearray(checkpoint), "state.bin"):
        with pytest.raises(hsid.DataError) as e:
            hsid.solve_many(wrong)
        assert e.value.kind == "not_a_list", str(e.value)
        assert "give a list of checkpoints' bytes" in str(e.value)
    with pytest.raises(hsid.DataError) as e:
        hsid.solve_many([checkpoint, "state.bin"])
    assert e.value.kind == "not_bytes" and "states[1] is a str" in str(e.value)
    with pytest.raises(hsid.DataError) as e:
        hsid.solve_many(3)
    assert e.value.kind == "not_a_list"
    # Bytes-likes and any iterable of them are taken.
    one = hsid.solve_checkpoint(checkpoint)
    got = hsid.solve_many(iter([checkpoint, bytearray(checkpoint), memoryview(checkpoint)]))
    assert got == [one, one, one]


def test_diagnose_takes_ts_and_units(record):
    _, u, y = record
    units = {"input": "V", "output": "deg"}
    report = hsid.diagnose(u, y, -1.0, 1.0, ts=0.01, units=units)
    assert report.pop("ts") == 0.01 and report.pop("units") == units
    assert report == hsid.diagnose(u, y, -1.0, 1.0)
    with pytest.raises(hsid.SettingsError) as e:
        hsid.diagnose(u, y, -1.0, 1.0, ts=-1.0)
    assert e.value.kind == "sample_time"
    with pytest.raises(hsid.SettingsError) as e:
        hsid.diagnose(u, y, -1.0, 1.0, units={"input": "V"})
    assert e.value.kind == "units"

