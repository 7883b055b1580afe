#!/usr/bin/env bash
# The Python package: builds its abi3 wheel (`maturin build --release`, with maturin from PyPI in
# the build venv target/py-build-venv), installs the wheel into a fresh venv (target/py-venv,
# made anew each run, with numpy, pytest, pytest-xdist, dask[distributed], nfoursid, pandas,
# scipy and control from PyPI; the venv scripts/python-overhead.sh and fleet-numbers.sh use),
# builds the `hsid` command line and the checkpoint maker its
# tests compare against, and runs the pytest suite against the installed wheel. A run that
# collects no test fails, and so do the peer comparisons when nfoursid or scipy is missing
# (HSID_REQUIRE_PEERS).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
venv=$root/target/py-build-venv
testvenv=$root/target/py-venv
wheels=$root/target/wheels

[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
# Through the venvs' interpreters and with VIRTUAL_ENV set here, never through an activate
# script or the venvs' scripts' #! lines: those name the path a venv was made at, so a copied
# venv would install into the original.
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check maturin
# HSID_PREBUILT=1: target/release/hsid and target/release/examples/make_checkpoint are built
# already (`.ci/run` runs the test command first, which builds both), else they are built here.
if [ -z "${HSID_PREBUILT:-}" ]; then
  cargo build --release --quiet -p hsid-host --bin hsid
  cargo build --release --quiet -p hsid-py --example make_checkpoint
fi
for b in target/release/hsid target/release/examples/make_checkpoint; do
  [ -x "$b" ] || { echo "$b is missing: build it, or run without HSID_PREBUILT" >&2; exit 1; }
done
# The wheel a user builds (`pip install ./python` builds the same), alone in target/wheels so
# that the one just built is the one installed.
rm -f "$wheels"/hsid-*.whl
(cd python && VIRTUAL_ENV=$venv PATH=$venv/bin:$PATH \
  "$venv/bin/python" -m maturin build --release --quiet --out "$wheels")
wheel=$(ls "$wheels"/hsid-*-abi3-*.whl)
rm -rf "$testvenv"
python3 -m venv "$testvenv"
"$testvenv/bin/python" -m pip install --quiet --disable-pip-version-check "$wheel" \
  numpy pytest pytest-xdist "dask[distributed]" nfoursid pandas scipy control
export VIRTUAL_ENV=$testvenv PATH=$testvenv/bin:$PATH

export HSID_BIN=$root/target/release/hsid
export HSID_MAKE_CHECKPOINT=$root/target/release/examples/make_checkpoint
export HSID_REQUIRE_PEERS=1
status=0
# The tests run in as many processes as the machine has cores (pytest-xdist;
# HSID_PYTEST_WORKERS=0 runs them in this one).
# From python/tests, not python/: the package imported is the installed wheel's, never the
# source folder python/hsid (which has no compiled extension).
(cd python/tests && "$testvenv/bin/python" -m pytest -n "${HSID_PYTEST_WORKERS:-auto}" .) || status=$?
if [ "$status" -eq 5 ]; then
  echo "pytest collected no test: the Python suite ran nothing" >&2
  exit 1
fi
exit "$status"
