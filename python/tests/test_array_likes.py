"""Array-likes in: lists, pandas Series, memoryviews and other dtypes read as numpy.asarray
reads them, to the same model as the float64 arrays."""

import numpy as np
import pandas as pd
import pytest

import hsid

PAPER = dict(refine=False, segments=7, f=10, p=10)


@pytest.fixture(scope="module")
def paper(record):
    _, u, y = record
    return hsid.identify(u, y, -1.0, 1.0, **PAPER)


@pytest.mark.parametrize(
    "convert", [list, tuple, pd.Series, memoryview], ids=["list", "tuple", "series", "memoryview"]
)
def test_array_likes_give_the_array_model(record, paper, convert):
    _, u, y = record
    model = hsid.identify(convert(u), convert(y), -1.0, 1.0, **PAPER)
    assert model == paper
    assert model.to_json() == paper.to_json()


def test_series_with_an_index_is_read_by_position(record, paper):
    _, u, y = record
    index = np.arange(len(u))[::-1] * 10
    model = hsid.identify(pd.Series(u, index=index), pd.Series(y, index=index), -1.0, 1.0, **PAPER)
    assert model == paper


def test_simulate_and_border_take_lists(paper, record):
    _, u, _ = record
    assert np.array_equal(paper.simulate(list(u[:500])), paper.simulate(u[:500]))
    assert np.array_equal(paper.border("ascending", [-0.5, 0.5]),
                          paper.border("ascending", np.array([-0.5, 0.5])))


def test_float32_and_big_endian_still_accepted(record):
    _, u, y = record
    m32 = hsid.identify(u.astype(np.float32), y.astype(np.float32), -1.0, 1.0, **PAPER)
    mbe = hsid.identify(u.astype(">f8"), y.astype(">f8"), -1.0, 1.0, **PAPER)
    assert mbe == hsid.identify(u, y, -1.0, 1.0, **PAPER)
    assert m32.order == mbe.order
