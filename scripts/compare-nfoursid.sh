#!/usr/bin/env bash
# hsid next to a peer: the Python package nfoursid (PyPI) on the same (z(t), ȳ(t)) records.
#
#   scripts/compare-nfoursid.sh [RUNS] [switch|backlash] [F] [METHOD]
#
# F is the horizon f = p of both (default 15: nfoursid's state-sequence step is biased by the
# coloured noise at f = p = 10, see docs/beyond-the-paper.md). METHOD is hsid's weighting:
# po-moesp by default (nfoursid's projection: past inputs and outputs as instruments; its
# system matrices come from the N4SID state sequence), or pi-moesp, n4sid, cva.
# Creates a virtual environment in target/nfoursid-venv (ignored by git), installs nfoursid,
# exports the paper's experiments with `cargo run --example export_zy`, runs nfoursid's
# subspace identification and hsid's on them, and prints both pole sets, their agreement and
# the time ratio. Exit status 1 if the poles do not agree.
set -euo pipefail
cd "$(dirname "$0")/.."

RUNS="${1:-10}"
CASE="${2:-switch}"
HORIZON="${3:-15}"
METHOD="${4:-po-moesp}"
VENV=target/nfoursid-venv
OUT=target/nfoursid/$CASE

if [ ! -x "$VENV/bin/python" ]; then
    python3 -m venv "$VENV"
fi
"$VENV/bin/pip" install --quiet --disable-pip-version-check nfoursid
echo "nfoursid $("$VENV/bin/python" -c 'import importlib.metadata as m; print(m.version("nfoursid"))'), numpy $("$VENV/bin/python" -c 'import numpy; print(numpy.__version__)')"

# HSID_EXPORT_ZY: an export_zy binary built already (`.ci/run` takes the one the test step
# built), else it is built here.
if [ -n "${HSID_EXPORT_ZY:-}" ]; then
    "$HSID_EXPORT_ZY" "$OUT" "$RUNS" "$CASE" "$HORIZON" "$METHOD"
else
    cargo run --release --quiet -p hsid-host --example export_zy -- "$OUT" "$RUNS" "$CASE" "$HORIZON" "$METHOD"
fi
"$VENV/bin/python" scripts/compare_nfoursid.py "$OUT"
