"""`Model.mean_gap` and `Model.std["gap"]`: the report's mean gap and its standard deviation, the
model file's (from the refinement's whole covariance of the borders); for a file without it,
first-order propagation of the border values' standard deviations, checked against a Monte
Carlo of the same border values."""

import json

import numpy as np
import pytest

import hsid

PAPER = dict(refine=False, segments=7, f=10, p=10)


@pytest.fixture(scope="module")
def refined(record):
    _, u, y = record
    return hsid.identify(u, y, -1.0, 1.0, fit="none")


def mean_gap_by_hand(m):
    """The mean of the defined gaps at 5 interior points, both directions, from `gap_at`."""
    points = m.u_min + (m.u_max - m.u_min) * np.arange(1, 6) / 6
    gaps = np.concatenate([m.gap_at("descending", points), m.gap_at("ascending", points)])
    return float(np.mean(gaps[~np.isnan(gaps)]))


def test_mean_gap_is_the_reports(refined, record, cli, tmp_path):
    assert refined.mean_gap == pytest.approx(mean_gap_by_hand(refined), rel=1e-12)
    # The servo's backlash is 0.2 V wide.
    assert abs(refined.mean_gap - 0.2) < 0.03
    # `hsid identify` prints the same number.
    import subprocess

    out = subprocess.run(
        [cli, "identify", "--data", record[0], "--umin", "-1", "--umax", "1", "--fit", "none"],
        check=True, capture_output=True, text=True,
    ).stdout
    line = next(l for l in out.splitlines() if l.startswith("mean gap "))
    value, pm, std, unit = line.removeprefix("mean gap ").split(" ")
    assert (pm, unit) == ("±", "V"), line
    half = 0.5 * 10.0 ** -len(value.split(".")[1])
    assert abs(float(value) - refined.mean_gap) <= half, line
    assert abs(float(std) - refined.std["gap"]) <= half, line


def test_gap_std_is_the_files(refined):
    # The refinement's whole covariance of the borders gives it (host-tests/tests/
    # gap_uncertainty.rs checks it against the spread over noise realisations).
    f = json.loads(refined.to_json())
    assert refined.std["gap"] == f["std"]["mean_gap"] > 0


def test_without_the_files_gap_std_it_matches_a_monte_carlo_of_the_border_values(refined):
    # A file written before the gap's standard deviation was stored: from the borders'
    # standard deviations, taken as uncorrelated.
    f = json.loads(refined.to_json())
    del f["std"]["mean_gap"]
    refined = hsid.Model.from_json(json.dumps(f))
    std = refined.std
    assert std is not None and std["gap"] > 0
    sa, sd = np.array(std["border_asc"]), np.array(std["border_desc"])
    assert sa[0] == sd[0]  # both borders start at μ0, one parameter
    rng = np.random.default_rng(7)
    draws = []
    for _ in range(1500):
        z0 = rng.standard_normal()
        g = dict(f)
        g["border_asc"] = list(np.array(f["border_asc"]) + sa * np.r_[z0, rng.standard_normal(len(sa) - 1)])
        g["border_desc"] = list(np.array(f["border_desc"]) + sd * np.r_[z0, rng.standard_normal(len(sd) - 1)])
        g["mu0"] = g["border_asc"][0]
        g["std"] = None
        draws.append(hsid.Model.from_json(json.dumps(g)).mean_gap)
    mc = np.std(draws, ddof=1)
    # 1,500 draws: the sample standard deviation is within 5 % of the truth at 2.7 sigma.
    assert std["gap"] == pytest.approx(mc, rel=0.05), (std["gap"], mc)
    assert np.mean(draws) == pytest.approx(refined.mean_gap, abs=3 * mc / np.sqrt(1500) + 1e-9)


def test_no_gap_where_there_is_none(record):
    _, u, y = record
    paper = hsid.identify(u, y, -1.0, 1.0, **PAPER)
    assert paper.std is None and paper.mean_gap is not None
    static = hsid.identify(u, y, -1.0, 1.0, nonlinearity="static", fit="none")
    assert static.mean_gap is None
    assert static.std is None or static.std["gap"] is None
