"""`Model` as a Python value: pickling, copying, equality and hashing through its model file;
its repr; the package's version."""

import copy
import pathlib
import pickle
import re

import numpy as np
import pytest

import hsid

PAPER = dict(refine=False, segments=7, f=10, p=10)


@pytest.fixture(scope="module")
def models(record):
    _, u, y = record
    paper = hsid.identify(u, y, -1.0, 1.0, ts=0.01, **PAPER)
    refined = hsid.identify(u, y, -1.0, 1.0, fit="none", ts=0.01)
    return paper, refined


def test_pickle_round_trip_is_equal(models):
    for m in models:
        again = pickle.loads(pickle.dumps(m))
        assert again == m and again is not m
        assert again.to_json() == m.to_json()
        assert again.notes == m.notes
        assert np.array_equal(again.simulate(np.zeros(50) - 1.0), m.simulate(np.zeros(50) - 1.0))


def test_copies_are_equal(models):
    m = models[1]
    assert copy.copy(m) == m and copy.deepcopy(m) == m
    assert copy.deepcopy([m, m])[0] == m


def test_equality_and_hash_follow_the_model_file(models):
    paper, refined = models
    again = hsid.Model.from_json(paper.to_json())
    assert again == paper and hash(again) == hash(paper)
    assert paper != refined and not (paper == refined)
    assert len({paper, again, refined}) == 2
    assert (paper == paper.to_json()) is False
    assert paper != None  # noqa: E711
    # A model read back has no notes but is still equal: notes are not the model.
    read_back = hsid.Model.from_json(refined.to_json())
    assert read_back.notes == [] and refined.notes != []
    assert read_back == refined and hash(read_back) == hash(refined)
    assert hsid.Model(paper.to_json()) == paper


def test_repr_is_python(models):
    paper, refined = models
    r = repr(paper)
    assert r.startswith("Model(order=2, nonlinearity='backlash', u=(-1.0, 1.0), segments=(7, 7)")
    assert r.endswith("refined=False)") and "refined=True)" in repr(refined)
    # Every keyword's value is a Python literal.
    body = re.fullmatch(r"Model\((.*)\)", r).group(1)
    values = eval(f"dict({body})")  # noqa: S307 (the package's own text)
    assert values["order"] == 2 and values["u"] == (-1.0, 1.0) and values["refined"] is False
    assert values["mu0"] == pytest.approx(paper.mu0, abs=1e-6)


def test_version_is_the_workspace_version():
    cargo = (pathlib.Path(__file__).resolve().parents[2] / "Cargo.toml").read_text()
    workspace = cargo[cargo.index("[workspace.package]") :]
    version = re.search(r'^version = "([^"]+)"', workspace, re.M).group(1)
    assert hsid.__version__ == version
