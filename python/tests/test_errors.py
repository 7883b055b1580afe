"""Every class of bad input raises the package's exception of its class, with a kind."""

import json

import numpy as np
import pytest

import hsid

PAPER = dict(refine=False, segments=7, f=10, p=10)


@pytest.fixture(scope="module")
def uy(record):
    return record[1], record[2]


def raises(cls, kind, fn, *args, **kwargs):
    with pytest.raises(cls) as info:
        fn(*args, **kwargs)
    assert isinstance(info.value, hsid.HsidError)
    assert info.value.kind == kind, str(info.value)
    assert str(info.value)
    return info.value


def test_hierarchy():
    for cls in (hsid.DataError, hsid.SettingsError, hsid.IdentificationError):
        assert issubclass(cls, hsid.HsidError) and issubclass(cls, Exception)


def test_wrong_dtypes_are_refused(uy):
    u, y = uy
    raises(hsid.DataError, "dtype", hsid.identify, u.astype(np.int64), y, -1.0, 1.0, **PAPER)
    raises(hsid.DataError, "dtype", hsid.identify, u, y.astype(object), -1.0, 1.0, **PAPER)
    raises(hsid.DataError, "dtype", hsid.identify, u, y.astype(complex), -1.0, 1.0, **PAPER)
    raises(hsid.DataError, "dtype", hsid.identify, u > 0, y, -1.0, 1.0, **PAPER)
    # Array-likes are read through numpy.asarray and checked as arrays are.
    raises(hsid.DataError, "dtype", hsid.identify, [bool(v > 0) for v in u], y, -1.0, 1.0, **PAPER)
    raises(hsid.DataError, "dtype", hsid.identify, [str(v) for v in u], y, -1.0, 1.0, **PAPER)
    raises(hsid.DataError, "dtype", hsid.identify, u, list(y.astype(complex)), -1.0, 1.0, **PAPER)
    e = raises(hsid.DataError, "not_an_array", hsid.identify, "u.csv", y, -1.0, 1.0, **PAPER)
    assert "u is a str" in str(e), str(e)
    raises(hsid.DataError, "not_an_array", hsid.identify, None, y, -1.0, 1.0, **PAPER)
    raises(hsid.DataError, "not_an_array", hsid.identify, {"u": 1.0}, y, -1.0, 1.0, **PAPER)
    raises(hsid.DataError, "not_an_array", hsid.identify, [[1.0], [1.0, 2.0]], y, -1.0, 1.0, **PAPER)
    raises(hsid.DataError, "shape", hsid.identify, [list(u)], y, -1.0, 1.0, **PAPER)


def test_two_dimensional_arrays_are_refused(uy):
    u, y = uy
    raises(hsid.DataError, "shape", hsid.identify, u.reshape(-1, 1), y, -1.0, 1.0, **PAPER)


def test_nan_is_refused_with_its_index(uy):
    u, y = uy
    bad = y.copy()
    bad[1234] = np.nan
    e = raises(hsid.DataError, "non_finite", hsid.identify, u, bad, -1.0, 1.0, **PAPER)
    assert "y[1234]" in str(e)


def test_mismatched_lengths_are_refused(uy):
    u, y = uy
    raises(hsid.DataError, "length_mismatch", hsid.identify, u, y[:-1], -1.0, 1.0, **PAPER)


def test_input_outside_the_interval_is_refused(uy):
    u, y = uy
    raises(hsid.DataError, "input_out_of_range", hsid.identify, u, y, -0.5, 1.0, **PAPER)


def test_bad_settings(uy):
    u, y = uy
    raises(hsid.SettingsError, "invalid_interval", hsid.identify, u, y, 1.0, -1.0)
    raises(hsid.SettingsError, "segments", hsid.identify, u, y, -1.0, 1.0, segments=0)
    raises(hsid.SettingsError, "nonlinearity", hsid.identify, u, y, -1.0, 1.0, nonlinearity="play")
    raises(hsid.SettingsError, "knot_endpoints", hsid.identify, u, y, -1.0, 1.0, knots=np.array([-0.9, 0.0, 1.0]))
    raises(hsid.SettingsError, "sample_time", hsid.identify, u, y, -1.0, 1.0, ts=-0.01)
    raises(hsid.SettingsError, "units", hsid.identify, u, y, -1.0, 1.0, units="V")
    raises(hsid.DataError, "all_hold", hsid.identify, u[:300], y[:300], -1.0, 1.0)


def test_a_refinement_too_large_for_the_record_is_refused_before_it_starts():
    # 10⁶ samples at order 40 (153 parameters with 14 segments a path): 2.3e12 multiply–adds
    # at the refinement's iteration limit, over the 1e12 a run may ask for; refused at once.
    t = np.arange(1_000_000)
    u = np.sin(2 * np.pi * t / 5000.0)
    y = 0.5 * u
    e = raises(hsid.SettingsError, "work", hsid.identify, u, y, -1.0, 1.0, hold=0, order=40)
    assert str(e).startswith("order=40 on 1000000 samples") and "refine=False" in str(e), str(e)


def test_unknown_keyword_is_a_type_error(uy):
    u, y = uy
    with pytest.raises(TypeError):
        hsid.identify(u, y, -1.0, 1.0, segmnets=7)
    with pytest.raises(TypeError):
        hsid.excite(-1.0, 1.0, 100, sead=3)


def test_constant_output_fails_the_identification(uy):
    u, _ = uy
    e = raises(hsid.IdentificationError, "no_dynamics", hsid.identify, u, np.zeros_like(u), -1.0, 1.0, **PAPER)
    assert e.kind == "no_dynamics"


def test_model_inputs_are_checked(record):
    _, u, y = record
    m = hsid.identify(u, y, -1.0, 1.0, **PAPER)
    raises(hsid.DataError, "input_out_of_range", m.simulate, u * 2, strict_interval=True)
    # By default the borders are extended beyond the interval, with a warning.
    with pytest.warns(UserWarning, match="outside the model's interval"):
        m.simulate(u * 2)
    raises(hsid.DataError, "input_out_of_range", m.border, "ascending", 1.5)
    raises(hsid.SettingsError, "direction", m.gap_at, "up", 0.0)


def test_bad_model_files():
    raises(hsid.DataError, "model_file_json", hsid.Model.from_json, "{")
    raises(hsid.DataError, "model_file_version", hsid.Model.from_json, json.dumps({"format": "hsid-model/0"}))


def test_bad_plant_spec(spec, uy):
    u, _ = uy
    bad = dict(spec, element={"kind": "backlash", "shape": "backlash", "gap": -0.2, "slope": 1.0})
    e = raises(hsid.SettingsError, "spec_out_of_range", hsid.simulate_plant, bad, u)
    assert "element.gap" in str(e)
    raises(hsid.SettingsError, "spec_json", hsid.simulate_plant, "{", u)
