"""`hsid.Model`: the model file round trip, the arrays it gives and its borders."""

import json

import numpy as np
import pytest

import hsid


@pytest.fixture(scope="module")
def model(record):
    _, u, y = record
    return hsid.identify(u, y, -1.0, 1.0, refine=False, segments=7, f=10, p=10)


def test_from_json_round_trip(model):
    text = model.to_json()
    again = hsid.Model.from_json(text)
    assert again.to_json() == text
    assert np.array_equal(again.A, model.A) and np.array_equal(again.poles, model.poles)


def test_arrays_follow_the_model_file(model):
    f = json.loads(model.to_json())
    assert f["format"] == "hsid-model/1"
    assert model.A.shape == (model.order, model.order) and model.A.dtype == np.float64
    assert np.array_equal(model.A, np.array(f["A"]))
    assert np.array_equal(model.B, f["B"]) and np.array_equal(model.C, f["C"])
    assert model.D == f["D"] and model.mu0 == f["mu0"]
    assert np.array_equal(model.knots_asc, f["knots_asc"])
    assert np.array_equal(model.knots_desc, f["knots_desc"])
    assert model.poles.dtype == np.complex128
    assert np.allclose(np.sort_complex(model.poles), np.sort_complex(np.linalg.eigvals(model.A)))
    assert model.nonlinearity == "backlash"
    assert "order=2" in repr(model)


def test_border_interpolates_between_knots(model):
    f = json.loads(model.to_json())
    k, v = np.array(f["knots_asc"]), np.array(f["border_asc"])
    assert np.array_equal(model.border("ascending", k), v)
    mid = (k[:-1] + k[1:]) / 2
    assert np.allclose(model.border("ascending", mid), (v[:-1] + v[1:]) / 2, rtol=0, atol=1e-12)
    assert model.border("descending", float(k[2])) == f["border_desc"][2]
    assert isinstance(model.border("ascending", 0), float)


def test_gap_is_the_distance_between_the_borders(model):
    # After an ascent to u the input must fall back to where the descending border takes
    # P_a(u): gap = u - P_d^-1(P_a(u)).
    u = 0.1
    g = model.gap_at("ascending", u)
    assert abs(model.border("descending", u - g) - model.border("ascending", u)) < 1e-12


def test_an_integrating_model_simulates_the_plant_output(model):
    f = json.loads(model.to_json())
    assert not model.integrating and "integrating" not in f
    f["integrating"] = True
    summed = hsid.Model.from_json(json.dumps(f))
    assert summed.integrating
    u = np.linspace(-1.0, 1.0, 200)
    # The stable part's output is the increments; the plant's output is their running sum.
    assert np.allclose(summed.simulate(u), np.cumsum(model.simulate(u)), rtol=0, atol=1e-9)
