"""`hsid.diagnose` returns the report `hsid diagnose --json` writes for the same record."""

import json
import subprocess

import numpy as np
import pytest

import hsid


def test_report_equals_the_command_line(record, cli, tmp_path):
    path, u, y = record
    out = tmp_path / "report.json"
    subprocess.run(
        [cli, "diagnose", "--data", path, "--umin", "-1", "--umax", "1", "--json", out],
        check=True, capture_output=True,
    )
    report = hsid.diagnose(u, y, -1.0, 1.0)
    assert report == json.loads(out.read_text())
    assert report["nonlinearity"] == "backlash"


def test_separate_validation_record(record):
    _, u, y = record
    report = hsid.diagnose(u[:4000], y[:4000], -1.0, 1.0, u_val=u, y_val=y)
    assert report["estimation_samples"] == 4000 and report["validation_samples"] == 6000
    assert "a separate record of 6300 samples" in report["data"]
    assert "scored from sample 300" in report["data"]


def test_bad_diagnose_input(record):
    _, u, y = record
    with pytest.raises(hsid.SettingsError) as info:
        hsid.diagnose(u, y, -1.0, 1.0, u_val=u)
    assert info.value.kind == "validation"
    with pytest.raises(hsid.SettingsError) as info:
        hsid.diagnose(u, y, -1.0, 1.0, split=1.5)
    assert info.value.kind == "invalid_split"
    with pytest.raises(hsid.DataError) as info:
        hsid.diagnose(u.astype(np.int32), y)
    assert info.value.kind == "dtype"
