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
