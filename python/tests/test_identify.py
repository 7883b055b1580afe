"""`hsid.identify` gives the model file the command line writes for the same record, bit for
bit, and recovers the simulated plant's poles and gap."""

import cmath
import math

import numpy as np
import pytest

import hsid
from conftest import HOLD, cli_model

UNITS = {"input": "V", "output": "deg"}


@pytest.fixture(scope="module")
def refined(record):
    """The default identification (segments, horizons and order from the data, refined)."""
    _, u, y = record
    return hsid.identify(u, y, -1.0, 1.0, ts=0.01, units=UNITS)


def test_excite_and_simulate_plant_equal_the_command_line(record, spec):
    _, u, y = record
    assert np.array_equal(hsid.excite(-1.0, 1.0, 6300, hold=HOLD, seed=1), u)
    assert np.array_equal(hsid.simulate_plant(spec, u, seed=1), y)


def test_default_identify_equals_hsid_identify_json(refined, record, cli, tmp_path):
    text = cli_model(
        cli, tmp_path, record[0], "--ts", "0.01", "--input-unit", "V", "--output-unit", "deg"
    )
    assert refined.to_json() == text


def test_paper_estimator_equals_hsid_identify_no_refine(record, cli, tmp_path):
    path, u, y = record
    # The record's header comments `# ts = 0.01 s`, `# input unit = V`, `# output unit = deg`
    # are its sample time and units for the command line; numpy arrays carry none, so they
    # are given here.
    model = hsid.identify(
        u, y, -1.0, 1.0, refine=False, segments=7, f=10, p=10, ts=0.01, units=UNITS
    )
    text = cli_model(cli, tmp_path, path, "--no-refine", "--segments", "7", "--f", "10", "--p", "10")
    assert model.to_json() == text
    assert model.std is None
    assert model.ts == 0.01 and model.units == UNITS


def test_refined_poles_and_gap_match_the_plant(refined, spec):
    # Second-order plant at 3 Hz, zeta 0.4, sampled at 100 Hz: z = exp(s ts).
    wn, zeta, ts = 2 * math.pi * spec["plant"]["fn_hz"], spec["plant"]["zeta"], spec["ts"]
    s = complex(-zeta * wn, wn * math.sqrt(1 - zeta**2))
    true = cmath.exp(s * ts)
    assert refined.order == 2
    poles = sorted(refined.poles, key=lambda p: p.imag)
    assert abs(poles[1] - true) < 1e-3
    assert abs(poles[0] - true.conjugate()) < 1e-3
    # The backlash's gap is 0.2 (H_a = u - 0.1, H_d = u + 0.1).
    for direction in ("ascending", "descending"):
        assert abs(refined.gap_at(direction, 0.0) - 0.2) < 0.03
    gaps = refined.gap_at("ascending", np.linspace(-0.5, 0.5, 5))
    assert gaps.shape == (5,) and np.all(np.abs(gaps - 0.2) < 0.05)
    # The borders straddle the true ones: P_d - P_a is the gap times the slope, up to gain.
    assert refined.std is not None
    assert set(refined.std) == {"poles", "mu0", "border_asc", "border_desc", "gap"}
    # The mean gap's standard deviation: small against the 0.2 V gap, but not zero.
    assert 0 < refined.std["gap"] < 0.03 and abs(refined.mean_gap - 0.2) < 0.03
    assert refined.ts == 0.01 and refined.units == UNITS


def fit(y, sim):
    """The simulation fit 1 - |y - sim| / |y - mean(y)| after the hold."""
    y, sim = y[HOLD:], sim[HOLD:]
    return 1 - np.linalg.norm(y - sim) / np.linalg.norm(y - y.mean())


def test_model_simulation_fits_the_record_as_the_true_plant_does(refined, record, spec):
    _, u, y = record
    sim = refined.simulate(u)
    assert sim.dtype == np.float64 and sim.shape == u.shape
    clean = hsid.simulate_plant({k: v for k, v in spec.items() if k != "noise"}, u)
    # The model fits the noisy record as well as the true plant's noise-free output does.
    assert abs(fit(y, sim) - fit(y, clean)) < 0.005, (fit(y, sim), fit(y, clean))


def test_float32_and_strided_inputs_are_converted(record):
    _, u, y = record
    base = hsid.identify(u, y, -1.0, 1.0, refine=False, segments=7, f=10, p=10)
    wide = np.empty(2 * u.size)
    wide[::2], wide[1::2] = u, y
    strided = hsid.identify(wide[::2], wide[1::2], -1.0, 1.0, refine=False, segments=7, f=10, p=10)
    assert strided.to_json() == base.to_json()
    # float32 samples are widened exactly; the model is that of the rounded record.
    u32, y32 = u.astype(np.float32), y.astype(np.float32)
    narrow = hsid.identify(u32, y32, -1.0, 1.0, refine=False, segments=7, f=10, p=10)
    same = hsid.identify(
        u32.astype(np.float64), y32.astype(np.float64), -1.0, 1.0, refine=False, segments=7, f=10, p=10
    )
    assert narrow.to_json() == same.to_json()
