#!/usr/bin/env bash
# The slow tier: what `.ci/run` leaves out to stay within its time budget, each part a claim
# of the docs that takes minutes to check.
#   tests       the tests marked `#[ignore = "slow tier, …"]`: the Monte Carlo runs (false
#               alarms, the generality goal over 20 random plants, the unit-root test, the
#               closed-loop bias over seeds), the confusion runs (every effect named first,
#               the second family's seeds) and the exhaustive power cuts of the checkpoint
#               store. (The one other ignored test, `thirty_million_samples_f32_tracks_f64`,
#               documents a limit and fails by design: docs/reliability.md, Long runs.)
#   fuzz        scripts/fuzz-smoke.sh: the four cargo-fuzz targets, 30 s each (FUZZ_SECONDS);
#               the first build instruments every dependency for coverage (minutes).
#   install     the README's first command, `cargo install --path host-tests` (into a temporary
#               root; a release build of its own, without the tests' dev-dependencies), and
#               the installed `hsid --version`.
#   exhaustion  scripts/exhaustion.sh: a 4 GB CSV, a 1 GB model file, 10^5 checkpoints (time
#               and peak memory; tens of minutes and gigabytes of temporary disk). ROWS and
#               STATES scale it down.
# SLOW_PARTS="tests fuzz" chooses the parts (default: all four). Each part is timed; the
# script stops at the first part that fails.
set -euo pipefail
cd "$(dirname "$0")/.."
parts=${SLOW_PARTS:-tests fuzz install exhaustion}

timed() {
  local name=$1
  shift
  local t0
  t0=$(date +%s)
  printf '\n=== slow tier: %s\n' "$name"
  "$@"
  printf '=== slow tier: %s passed in %d s\n' "$name" $(($(date +%s) - t0))
}

if [[ " $parts " == *" tests "* ]]; then
  timed tests cargo test --workspace --release -- --ignored \
    --skip thirty_million_samples_f32_tracks_f64
fi
if [[ " $parts " == *" fuzz "* ]]; then
  if rustup run nightly rustc --version >/dev/null 2>&1 && ! cargo +nightly fuzz --version >/dev/null 2>&1; then
    cargo install cargo-fuzz --locked --quiet
  fi
  timed fuzz scripts/fuzz-smoke.sh
fi
if [[ " $parts " == *" install "* ]]; then
  root=$(mktemp -d)
  timed install cargo install --path host-tests --root "$root" --target-dir target --locked --quiet
  "$root/bin/hsid" --version
  rm -rf "$root"
fi
if [[ " $parts " == *" exhaustion "* ]]; then
  cargo build --release -p hsid-host --bin hsid
  timed exhaustion scripts/exhaustion.sh
fi
