"""The simulated fleet the fleet tests share."""

import subprocess

import pytest


@pytest.fixture(scope="session")
def fleet(cli, tmp_path_factory):
    """A fleet of 6 devices × 3 weeks with 1,000 samples a week: the directory of checkpoints
    and the devices' file names, sorted."""
    root = tmp_path_factory.mktemp("fleet")
    states = root / "states"
    subprocess.run(
        [cli, "fleet", "simulate", "--devices", "6", "--weeks", "3", "--samples", "1000",
         "--out", states, "--truth", root / "truth.csv"],
        check=True, capture_output=True,
    )
    names = sorted(p.name for p in states.iterdir())
    assert len(names) == 18
    return states, names
