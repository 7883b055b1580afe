"""`hsid.identify` and `hsid identify` are two faces of one library workflow: on a record that
takes each of its routes (the element fitted by simulation error, the closed-loop estimate
from a logged reference, an integrating plant) they write the same model file, and Python
says what was done in `Model.notes`."""

import subprocess

import numpy as np
import pytest

import hsid
from conftest import SPEC


def write_csv(path, columns):
    names = list(columns)
    rows = np.column_stack([columns[n] for n in names])
    np.savetxt(path, rows, delimiter=",", header=",".join(names), comments="", fmt="%.17g")


def cli_json(cli, tmp_path, csv, *flags):
    out = tmp_path / "model.json"
    run = subprocess.run(
        [cli, "identify", "--data", csv, *flags, "--json", out], capture_output=True, text=True
    )
    assert run.returncode == 0, run.stderr
    return out.read_text(), run.stdout


@pytest.fixture(scope="module")
def inner_loops(cli, tmp_path_factory):
    """The servo of the documentation driven by an input that reverses inside [-1, 1] (random
    levels held 25 samples, a fifth of them at an end, smoothed over 10 samples: not the
    Table I sweeps), after a hold of 300 samples at -1."""
    rng = np.random.default_rng(3)
    levels = rng.uniform(-1.0, 1.0, 121)
    ends = rng.random(levels.size) < 0.2
    levels[ends] = rng.choice([-1.0, 1.0], ends.sum())
    u = np.convolve(np.repeat(levels, 25)[:3000], np.ones(10) / 10, mode="same")
    u[:300] = -1.0
    path = tmp_path_factory.mktemp("inner") / "u.csv"
    write_csv(path, {"u": u})
    csv = subprocess.run(
        [cli, "simulate", "--plant", SPEC, "--input", path, "--seed", "3"],
        check=True, capture_output=True,
    ).stdout
    record = path.with_name("servo.csv")
    record.write_bytes(csv)
    data = np.loadtxt(record, delimiter=",", comments="#", skiprows=4)
    return record, np.ascontiguousarray(data[:, 0]), np.ascontiguousarray(data[:, 1])


def test_the_element_fit_route_is_the_same_in_python(inner_loops, cli, tmp_path):
    path, u, y = inner_loops
    text, stdout = cli_json(cli, tmp_path, path, "--umin", "-1", "--umax", "1")
    assert "--fit auto:" in stdout
    model = hsid.identify(u, y, -1.0, 1.0, ts=0.01, units={"input": "V", "output": "deg"})
    assert model.to_json() == text
    assert '"element": "play"' in text
    # Its repr says how it was fitted (not "refined=False", which reads as a failure).
    assert "element='play', fit='simulation-error'" in repr(model), repr(model)
    fit_notes = [n for n in model.notes if n.startswith('fit="auto": ')]
    assert len(fit_notes) == 1, model.notes
    assert 'fit="none" keeps the two-path model' in fit_notes[0]
    # The data checks, in the command line's words: the input breaks the Table I structure.
    checks = [n for n in model.notes if n.startswith("data checks: ")]
    assert len(checks) == 1 and checks[0] in stdout, (checks, stdout)
    assert "of 7 passed" in checks[0] and "warning [table1_structure]" in stdout
    # The play's gap is the servo's 0.2 V: the model simulates the play itself.
    assert abs(model.gap_at("ascending", 0.0) - 0.2) < 0.05
    sim = model.simulate(u)
    nrmse = np.sqrt(np.mean((sim[300:] - y[300:]) ** 2)) / np.std(y[300:])
    assert nrmse < 0.15, nrmse
    none = hsid.identify(u, y, -1.0, 1.0, fit="none")
    assert '"element"' not in none.to_json()
    assert "refined=True" in repr(none), repr(none)
    with pytest.raises(hsid.SettingsError) as e:
        hsid.identify(u, y, -1.0, 1.0, fit="sometimes")
    assert e.value.kind == "fit"


def closed_loop_servo(seed):
    """A servo under proportional control with a dither, written apart from the library: a
    play of width 0.4 on [-3, 3] before a second-order plant (poles 0.9429 ± 0.1255j, unit
    static gain), output noise 0.02; a hold of 100 samples at -3 in open loop first."""
    rng = np.random.default_rng(seed)
    n, hold = 4000, 100
    a1, a2 = 1.8858, -0.9048
    gain = 1 - a1 - a2
    r = np.repeat(rng.uniform(-2.0, 2.0, n // 50 + 1), 50)[:n]
    r[:hold] = -3.0
    u, y, x = np.empty(n), np.empty(n), np.zeros(n + 2)
    w = -3.0 + 0.2
    for t in range(n):
        y[t] = x[t + 1] + 0.02 * rng.standard_normal()
        if t < hold:
            u[t] = -3.0
        else:
            u[t] = np.clip(0.8 * (r[t] - y[t]) + 0.6 * rng.standard_normal(), -3.0, 3.0)
        w = min(max(w, u[t] - 0.2), u[t] + 0.2)
        x[t + 2] = a1 * x[t + 1] + a2 * x[t] + gain * w
    return u, y, r


def test_the_closed_loop_route_is_the_same_in_python(cli, tmp_path):
    u, y, r = closed_loop_servo(5)
    path = tmp_path / "loop.csv"
    write_csv(path, {"u": u, "y": y, "r": r})
    flags = ["--umin", "-3", "--umax", "3", "--hold", "100", "--reference-column", "r"]
    text, stdout = cli_json(cli, tmp_path, path, *flags)
    assert "closed loop: the model is estimated with instruments" in stdout
    model = hsid.identify(u, y, -3.0, 3.0, hold=100, reference=r)
    assert model.to_json() == text
    assert any(n.startswith("closed loop:") for n in model.notes)
    poles = sorted(model.poles, key=lambda p: p.imag)
    assert abs(poles[-1] - complex(0.9429, 0.1255)) < 0.02, poles
    with pytest.raises(hsid.DataError) as e:
        hsid.identify(u, y, -3.0, 3.0, hold=100, reference=r[:-1])
    assert e.value.kind == "length_mismatch"
    with pytest.raises(hsid.SettingsError) as e:
        hsid.identify(u, y, -3.0, 3.0, hold=100, reference=r, nonlinearity="static")
    assert e.value.kind == "reference_static"
    assert 'drop nonlinearity="static"' in str(e.value)


def test_the_integrating_route_is_the_same_in_python(record, cli, tmp_path):
    # The servo's output summed: a plant with an integrator behind the same backlash.
    path, u, y = record
    position = np.cumsum(y)
    csv = tmp_path / "position.csv"
    write_csv(csv, {"u": u, "y": position})
    flags = ["--umin", "-1", "--umax", "1", "--integrating", "--segments", "7", "--order", "2"]
    text, stdout = cli_json(cli, tmp_path, csv, *flags)
    model = hsid.identify(u, position, -1.0, 1.0, integrating=True, segments=7, order=2)
    assert model.to_json() == text
    assert model.integrating
    assert model.notes[0].startswith("integrating: one pole fixed at z = 1")
    # The stable part is the servo's plant: its increments are the servo's output.
    sim = model.simulate(u)
    assert np.corrcoef(np.diff(sim)[400:], y[401:])[0, 1] > 0.9
