"""The linear part for the control world (`to_dlti`, `to_control`) and the element as its own
callable (`element`): driven by the element's output from the model's rest state, the linear
part gives the model's simulation."""

import numpy as np
import pytest

import hsid

PAPER = dict(refine=False, segments=7, f=10, p=10)
signal = pytest.importorskip("scipy.signal", reason="scipy is not installed: pip install scipy")
control = pytest.importorskip("control", reason="python-control is not installed: pip install control")


@pytest.fixture(scope="module")
def model(record):
    _, u, y = record
    return hsid.identify(u, y, -1.0, 1.0, ts=0.01, **PAPER)


def rest(m):
    """The state at rest on μ0: x = (I - A)^-1 B μ0."""
    return np.linalg.solve(np.eye(m.order) - m.A, m.B * m.mu0)


def test_element_takes_the_border_of_each_direction(model):
    # From rest at u_min the first sample stays descending; then up, then back down.
    h = model.element([-1.0, 0.5, 0.2, 0.2])
    assert isinstance(h, np.ndarray) and h.shape == (4,)
    assert h[0] == model.border("descending", -1.0)
    assert h[1] == model.border("ascending", 0.5)
    assert h[2] == model.border("descending", 0.2)
    assert h[3] == model.border("descending", 0.2)
    assert model.element(-1.0) == model.border("descending", -1.0)
    with pytest.raises(hsid.DataError) as e:
        model.element([0.0, 2.0], strict_interval=True)
    assert e.value.kind == "input_out_of_range"
    with pytest.warns(UserWarning, match="outside the model's interval"):
        model.element(np.array([0.0, 1.5]))


def test_dlti_driven_by_the_element_is_the_simulation(model, record):
    _, u, _ = record
    sys = model.to_dlti()
    assert isinstance(sys, signal.dlti) and sys.dt == 0.01
    ss = sys.to_ss() if hasattr(sys, "to_ss") else sys
    assert ss.B.shape == (model.order, 1) and ss.C.shape == (1, model.order)
    assert np.array_equal(ss.A, model.A) and np.array_equal(ss.B[:, 0], model.B)
    assert np.array_equal(ss.C[0], model.C) and ss.D[0, 0] == model.D
    _, y, _ = signal.dlsim(sys, model.element(u), x0=rest(model))
    sim = model.simulate(u)
    assert np.max(np.abs(y[:, 0] - sim)) < 1e-9 * np.max(np.abs(sim))


def test_dlti_step_response_ends_at_the_static_gain(model):
    _, (step,) = model.to_dlti().step(n=3000)
    gain = model.C @ np.linalg.solve(np.eye(model.order) - model.A, model.B) + model.D
    assert step[-1, 0] == pytest.approx(gain, rel=1e-6)


def test_control_state_space_is_the_simulation(model, record):
    _, u, _ = record
    sys = model.to_control()
    assert isinstance(sys, control.StateSpace) and sys.dt == 0.01
    assert np.array_equal(sys.A, model.A) and np.array_equal(np.asarray(sys.B)[:, 0], model.B)
    r = control.forced_response(sys, U=model.element(u), X0=rest(model))
    sim = model.simulate(u)
    assert np.max(np.abs(np.ravel(r.outputs) - sim)) < 1e-9 * np.max(np.abs(sim))
    assert control.dcgain(sys) == pytest.approx(
        model.C @ np.linalg.solve(np.eye(model.order) - model.A, model.B) + model.D, rel=1e-9
    )


def test_without_a_sample_time_dt_is_true(record):
    _, u, y = record
    m = hsid.identify(u, y, -1.0, 1.0, **PAPER)
    assert m.to_dlti().dt is True
    assert m.to_control().dt is True
