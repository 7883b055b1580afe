"""`hsid.solve_checkpoint`: an onboard identifier's checkpoint solves to the model the paper's
estimator gives on the same record, and corrupt bytes raise a DataError."""

import numpy as np
import pytest

import hsid


def test_checkpoint_solves_to_the_direct_identification(checkpoint, record):
    _, u, y = record
    solved = hsid.solve_checkpoint(checkpoint)
    direct = hsid.identify(u, y, -1.0, 1.0, refine=False, segments=7, f=10, p=10)
    # The same accumulation and solve in f64: bit for bit.
    assert solved.order == direct.order
    for name in ("A", "B", "C", "knots_asc", "knots_desc"):
        assert np.array_equal(getattr(solved, name), getattr(direct, name)), name
    assert solved.D == direct.D and solved.mu0 == direct.mu0
    k = direct.knots_asc
    assert np.array_equal(solved.border("ascending", k), direct.border("ascending", k))
    # A checkpoint does not record which two-path element it is.
    assert solved.nonlinearity is None


@pytest.mark.parametrize(
    "corrupt, kind",
    [
        (lambda b: b[: len(b) // 2], "checkpoint_truncated"),
        (lambda b: b"not a checkpoint" + b[16:], "not_a_checkpoint"),
        (lambda b: b[:-9] + bytes([b[-9] ^ 0xFF]) + b[-8:], "checkpoint_checksum"),
    ],
)
def test_corrupt_checkpoints_raise_data_errors(checkpoint, corrupt, kind):
    with pytest.raises(hsid.DataError) as info:
        hsid.solve_checkpoint(corrupt(checkpoint))
    assert info.value.kind == kind, str(info.value)


def markov(model, count):
    """D, CB, CAB, …: the model's impulse response, which no choice of state basis changes."""
    a, b, c = np.asarray(model.A), np.asarray(model.B), np.asarray(model.C)
    out, x = [model.D], b
    for _ in range(count):
        out.append(float(c @ x))
        x = a @ x
    return np.array(out)


def test_the_structured_solve_gives_the_dense_model_to_rounding(checkpoint):
    dense = hsid.solve_checkpoint(checkpoint)
    structured = hsid.solve_checkpoint(checkpoint, solver="structured")
    assert structured.order == dense.order
    # A, B, C are in a state basis of each solve's own (a singular vector's sign may differ):
    # compare what does not depend on it.
    assert np.allclose(markov(structured, 40), markov(dense, 40), rtol=1e-9, atol=1e-12)
    assert np.allclose(np.sort_complex(np.linalg.eigvals(structured.A)),
                       np.sort_complex(np.linalg.eigvals(dense.A)), rtol=1e-9, atol=1e-12)
    k = dense.knots_asc
    for side in ("ascending", "descending"):
        assert np.allclose(structured.border(side, k), dense.border(side, k), rtol=1e-9, atol=1e-12)
    assert structured.mu0 == dense.mu0


def test_an_unknown_solver_is_a_settings_error(checkpoint):
    with pytest.raises(hsid.SettingsError) as info:
        hsid.solve_checkpoint(checkpoint, solver="fast")
    assert info.value.kind == "solver", str(info.value)
    with pytest.raises(TypeError):
        hsid.solve_checkpoint(checkpoint, solver=3)
