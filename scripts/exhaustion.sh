#!/usr/bin/env bash
# Resource exhaustion on the host: peak memory (GNU time -v) of hsid on a 1 GB model file and
# on a directory of 10^5 checkpoints. Not run by CI (it writes large files into a temporary
# directory); run it by hand after `cargo build --release -p hsid-host`.
set -euo pipefail
cd "$(dirname "$0")/.."
hsid=target/release/hsid
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
peak() { /usr/bin/time -v "$@" 2>&1 >/dev/null | grep -E 'Maximum resident|Elapsed|^hsid:' || true; }

echo "== model file of 1 GB (sparse): refused before reading"
truncate -s 1G "$tmp/big.json"
peak "$hsid" validate --model "$tmp/big.json" --data examples/data/servo-check.csv

echo "== directory of 10^5 checkpoints: listing cost"
state=${STATE:?give STATE=<a checkpoint file written by Identifier::save>}
mkdir "$tmp/states"
for i in $(seq 1 100000); do ln "$state" "$tmp/states/$i.bin" 2>/dev/null || cp "$state" "$tmp/states/$i.bin"; done
peak ls -f "$tmp/states"
echo "== hsid solve --state on one of them"
peak "$hsid" solve --state "$tmp/states/50000.bin"
