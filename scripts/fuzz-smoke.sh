#!/usr/bin/env bash
# Fuzz smoke: builds the cargo-fuzz targets in fuzz/ once, then runs each for a short bounded
# time (default 30 s each, FUZZ_SECONDS overrides) from the committed corpus, one process, and
# prints its executions. Needs a nightly toolchain and cargo-fuzz; without them it prints a
# SKIP line and succeeds. A crash, a hang (an input slower than 10 s), a leak of memory
# beyond 2 GB or a target that executed nothing fails the script; the input is left in
# fuzz/artifacts/<target>/.
#
# The long runs of docs/reliability.md are this script with FUZZ_SECONDS=600 and
# FUZZ_WORK=<dir>: the corpus then grows in <dir>/<target> (seeded from the committed one) and
# is kept with the log, for `cargo fuzz cmin`. FUZZ_TARGETS="a b" runs only those targets;
# FUZZ_RUNS=N stops each target after N executions (or FUZZ_SECONDS, whichever comes first).
#
# Build flags: release with debug assertions and overflow checks (-O -a), no sanitizer
# (-s none: the fuzzed crates forbid unsafe code; an overflow or a failed check panics).
# The first build compiles every dependency with coverage instrumentation (minutes); it is
# timed separately so that a slow build is not mistaken for a slow target.
set -euo pipefail
cd "$(dirname "$0")/../fuzz"

seconds=${FUZZ_SECONDS:-30}
read -r -a targets <<<"${FUZZ_TARGETS:-restore model_file csv push_solve}"
flags=(-O -a -s none)

if ! rustup run nightly rustc --version >/dev/null 2>&1; then
  echo "SKIP fuzz smoke: no nightly toolchain (rustup toolchain install nightly)"
  exit 0
fi
if ! cargo +nightly fuzz --version >/dev/null 2>&1; then
  echo "SKIP fuzz smoke: cargo-fuzz is not installed (cargo install cargo-fuzz)"
  exit 0
fi

start=$(date +%s)
cargo +nightly fuzz build "${flags[@]}"
echo "fuzz build: $(($(date +%s) - start)) s"

for t in "${targets[@]}"; do
  mkdir -p "corpus/$t"
  # Work on a copy so that the run does not grow the committed corpus.
  if [ -n "${FUZZ_WORK:-}" ]; then
    work="$FUZZ_WORK/$t"
    mkdir -p "$work"
  else
    work=$(mktemp -d)
  fi
  cp -r "corpus/$t/." "$work/"
  set +e
  t0=$(date +%s)
  cargo +nightly fuzz run "${flags[@]}" "$t" "$work" -- -max_total_time="$seconds" \
    ${FUZZ_RUNS:+-runs="$FUZZ_RUNS"} \
    -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 >"$work.log" 2>&1
  status=$?
  elapsed=$(($(date +%s) - t0))
  set -e
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work.log")
  keep() { [ -n "${FUZZ_WORK:-}" ] || rm -rf "$work" "$work.log"; }
  if [ "$status" -ne 0 ] || [ -z "$runs" ] || [ "$runs" -eq 0 ]; then
    tail -30 "$work.log" >&2
    keep
    echo "fuzz $t: FAILED (exit $status, ${runs:-no} executions), input in fuzz/artifacts/$t/" >&2
    exit 1
  fi
  grep '^stat::' "$work.log" | sed "s/^/fuzz $t: /"
  echo "fuzz $t: $runs executions (at most ${FUZZ_RUNS:-unbounded} in at most $seconds s) in $elapsed s, no crash"
  keep
done
echo "fuzz smoke: ${#targets[@]} targets ran (each at most ${seconds} s${FUZZ_RUNS:+ or $FUZZ_RUNS executions}) without a crash or a hang"
