"""`hsid.identify(..., friction=True)` is the face of `hsid identify --friction`: on the EMPS
positioning drive (read from ../shared/data/, the benchmark's own files) both write the same
model file, the notes read the model as a rigid body near the benchmark's reference model
(M = 95.1089 kg, F_c = 20.3935 N, identified by inverse dynamics; the simulation-error fit
reads 91.16 kg and 22.57 N and simulates both records better: docs/friction.md), and
`Model.simulate` runs the model with friction."""

import json
import pathlib
import subprocess

import numpy as np
import pytest

import hsid
from conftest import ROOT

EMPS = ROOT.parent / "shared" / "data" / "emps" / "emps_train.csv"


@pytest.mark.skipif(not EMPS.is_file(), reason="the EMPS record is not beside the project")
def test_friction_is_one_workflow_with_the_command_line(cli, tmp_path):
    data = np.genfromtxt(EMPS, delimiter=",", names=True)
    u, y = data["force_N"], data["qm"]
    model = hsid.identify(
        u, y, -160.0, 150.0, hold=0, integrating=True, nonlinearity="static", segments=1,
        order=1, friction=True, ts=1e-3, units={"input": "N", "output": "m"},
    )
    body = [n for n in model.notes if n.startswith("friction: as a rigid body")]
    assert len(body) == 1, model.notes
    mass = float(body[0].split("mass ")[1].split()[0])
    coulomb = float(body[0].split("Coulomb friction ")[1].split()[0])
    assert abs(mass - 95.1089) < 0.05 * 95.1089, body
    assert abs(coulomb - 20.3935) < 0.12 * 20.3935, body
    out = tmp_path / "model.json"
    run = subprocess.run(
        [cli, "identify", "--data", EMPS, "--input-column", "force_N", "--output-column", "qm",
         "--input-unit", "N", "--output-unit", "m", "--umin", "-160", "--umax", "150",
         "--hold", "0", "--integrating", "--nonlinearity", "static", "--segments", "1",
         "--order", "1", "--friction", "--json", out],
        capture_output=True, text=True,
    )
    assert run.returncode == 0, run.stderr
    cli_file = json.loads(out.read_text())
    py_file = json.loads(model.to_json())
    assert cli_file["friction"] == py_file["friction"]
    assert cli_file["A"] == py_file["A"] and cli_file["B"] == py_file["B"]
    # From rest at the position 0: a force above the friction moves the drive up, one below
    # its negative moves it down, one inside it leaves it nearly still.
    for force, sign in [(60.0, 1.0), (-60.0, -1.0)]:
        pos = model.simulate(np.full(2000, force))
        assert np.sign(pos[-1]) == sign and abs(pos[-1]) > 1e-3, (force, pos[-1])
    still = model.simulate(np.full(2000, 3.0))
    assert abs(still[-1]) < 0.05 * abs(model.simulate(np.full(2000, 60.0))[-1])
