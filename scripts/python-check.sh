#!/usr/bin/env bash
# The Python package: builds it into a virtual environment (target/py-venv; maturin, numpy,
# pytest, dask[distributed] and nfoursid from PyPI), builds the `hsid` command line and the
# checkpoint maker its tests compare against, and runs the pytest suite. A run that collects
# no test fails.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
venv=$root/target/py-venv

[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/pip" install --quiet --disable-pip-version-check maturin numpy pytest "dask[distributed]" nfoursid
cargo build --release --quiet -p hsid-host --bin hsid
cargo build --release --quiet -p hsid-py --example make_checkpoint
# shellcheck disable=SC1091
. "$venv/bin/activate"
(cd python && maturin develop --release --quiet)

export HSID_BIN=$root/target/release/hsid
export HSID_MAKE_CHECKPOINT=$root/target/release/examples/make_checkpoint
status=0
(cd python && python -m pytest tests) || status=$?
if [ "$status" -eq 5 ]; then
  echo "pytest collected no test: the Python suite ran nothing" >&2
  exit 1
fi
exit "$status"
