"""Shared fixtures: the `hsid` command line, the servo record it makes, and the checkpoint an
onboard identifier saves after that record."""

import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SPEC = ROOT / "examples" / "data" / "servo-backlash.json"
HOLD = 300


def binary(name, env, default):
    path = pathlib.Path(os.environ.get(env, ROOT / "target" / "release" / default))
    if not path.is_file():
        pytest.fail(f"{path} is missing: build it first (scripts/python-check.sh does), or set {env}")
    return path


@pytest.fixture(scope="session")
def cli():
    """The `hsid` command line."""
    return binary("hsid", "HSID_BIN", "hsid")


@pytest.fixture(scope="session")
def spec():
    """The servo with gearbox backlash of the documentation (3 Hz, zeta 0.4, gap 0.2, 20 dB)."""
    return json.loads(SPEC.read_text())


@pytest.fixture(scope="session")
def record(cli, tmp_path_factory):
    """The servo record `hsid excite | hsid simulate --plant` writes (seed 1): the CSV path,
    u and y."""
    path = tmp_path_factory.mktemp("record") / "servo.csv"
    u = subprocess.run(
        [cli, "excite", "--umin", "-1", "--umax", "1", "--samples", "6300", "--hold", str(HOLD), "--seed", "1"],
        check=True, capture_output=True,
    ).stdout
    csv = subprocess.run(
        [cli, "simulate", "--plant", SPEC, "--input", "-", "--seed", "1"],
        input=u, check=True, capture_output=True,
    ).stdout
    path.write_bytes(csv)
    data = np.loadtxt(path, delimiter=",", comments="#", skiprows=4)
    return path, np.ascontiguousarray(data[:, 0]), np.ascontiguousarray(data[:, 1])


def cli_model(cli, tmp_path, csv, *flags):
    """The model file `hsid identify --json` writes for the record `csv`, as text."""
    out = tmp_path / "model.json"
    subprocess.run(
        [cli, "identify", "--data", csv, "--umin", "-1", "--umax", "1", *flags, "--json", out],
        check=True, capture_output=True,
    )
    return out.read_text()


@pytest.fixture(scope="session")
def checkpoint(record, tmp_path_factory):
    """The checkpoint of an f64 identifier (7 + 7 segments, f = p = 10) fed the record."""
    tool = binary("make_checkpoint", "HSID_MAKE_CHECKPOINT", "examples/make_checkpoint")
    out = tmp_path_factory.mktemp("state") / "state.bin"
    subprocess.run([tool, record[0], "-1", "1", "7", str(HOLD), out], check=True)
    return out.read_bytes()
