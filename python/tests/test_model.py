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


def test_simulate_extends_the_borders_beyond_the_interval_and_warns(model, record):
    import warnings

    _, u_rec, _ = record
    f = json.loads(model.to_json())
    inside = np.ascontiguousarray(u_rec[:1000])
    assert inside.min() >= model.u_min and inside.max() <= model.u_max
    u = np.concatenate([inside, np.full(2000, 1.3), np.full(2000, -1.2)])
    with pytest.warns(UserWarning) as caught:
        y = model.simulate(u)
    assert len(caught) == 1
    text = str(caught[0].message)
    # The interval as the library writes numbers: -1 and 1, not -1.0 and 1.0.
    assert (model.u_min, model.u_max) == (-1.0, 1.0)
    assert text.startswith("4000 of 5000 samples (80.00 %) lie outside the model's interval [-1, 1]"), text
    assert "(lowest -1.2, highest 1.3)" in text
    assert text.endswith("the borders are extended linearly beyond it (strict_interval=True refuses instead)")
    # While the input stays inside, the output is the strict simulation of that part, without
    # a warning.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        strict = model.simulate(inside, strict_interval=True)
    assert np.allclose(y[:1000], strict, rtol=0, atol=1e-12)
    # Held beyond the interval the output settles on the line through the two end knots of
    # the border of the direction, times the static gain G(1) = C (I - A)^-1 B + D.
    A, B, C = np.array(f["A"]), np.array(f["B"]), np.array(f["C"])
    gain = C @ np.linalg.solve(np.eye(len(B)) - A, B) + f["D"]

    def line(k, v, i, j, x):
        return v[i] + (v[j] - v[i]) * (x - k[i]) / (k[j] - k[i])

    ka, va = f["knots_asc"], f["border_asc"]
    kd, vd = f["knots_desc"], f["border_desc"]
    assert abs(y[2999] - gain * line(ka, va, -2, -1, 1.3)) < 1e-6 * max(1.0, abs(y[2999]))
    assert abs(y[-1] - gain * line(kd, vd, 0, 1, -1.2)) < 1e-6 * max(1.0, abs(y[-1]))


def test_simulate_with_strict_interval_refuses_an_input_outside(model):
    u = np.array([model.u_min, 0.0, 1.3, 0.0])
    with pytest.raises(hsid.DataError) as info:
        model.simulate(u, strict_interval=True)
    assert info.value.kind == "input_out_of_range"
    assert "u[2] = 1.3 lies outside the model's input interval" in str(info.value)
