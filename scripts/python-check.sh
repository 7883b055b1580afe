#!/usr/bin/env bash
# The Python package: builds it into a virtual environment (target/py-venv; maturin, numpy,
# pytest, pytest-xdist, dask[distributed], nfoursid, pandas and scipy from PyPI), builds the `hsid` command
# line and the checkpoint maker its tests compare against, and runs the pytest suite. A run that
# collects no test fails, and so do the peer comparisons when nfoursid or scipy is missing
# (HSID_REQUIRE_PEERS).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
venv=$root/target/py-venv

[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
# Through the venv's interpreter and with VIRTUAL_ENV set here, never through its activate
# script or its scripts' #! lines: those name the path the venv was made at, so a copied venv
# would install into the original.
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check maturin numpy pytest pytest-xdist "dask[distributed]" nfoursid pandas scipy
# HSID_PREBUILT=1: target/release/hsid and target/release/examples/make_checkpoint are built
# already (`.ci/run` runs the test command first, which builds both), else they are built here.
if [ -z "${HSID_PREBUILT:-}" ]; then
  cargo build --release --quiet -p hsid-host --bin hsid
  cargo build --release --quiet -p hsid-py --example make_checkpoint
fi
for b in target/release/hsid target/release/examples/make_checkpoint; do
  [ -x "$b" ] || { echo "$b is missing: build it, or run without HSID_PREBUILT" >&2; exit 1; }
done
export VIRTUAL_ENV=$venv PATH=$venv/bin:$PATH
(cd python && "$venv/bin/python" -m maturin develop --release --quiet)

export HSID_BIN=$root/target/release/hsid
export HSID_MAKE_CHECKPOINT=$root/target/release/examples/make_checkpoint
export HSID_REQUIRE_PEERS=1
status=0
# The tests run in as many processes as the machine has cores (pytest-xdist;
# HSID_PYTEST_WORKERS=0 runs them in this one).
(cd python && "$venv/bin/python" -m pytest -n "${HSID_PYTEST_WORKERS:-auto}" tests) || status=$?
if [ "$status" -eq 5 ]; then
  echo "pytest collected no test: the Python suite ran nothing" >&2
  exit 1
fi
exit "$status"
