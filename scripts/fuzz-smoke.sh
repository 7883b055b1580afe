#!/usr/bin/env bash
# Fuzz smoke: runs every cargo-fuzz target in fuzz/ for a short bounded time (default 30 s each,
# FUZZ_SECONDS overrides) from the committed corpus. Needs a nightly toolchain and cargo-fuzz;
# without them it prints a SKIP line and succeeds. A crash or a hang fails the script and leaves
# the input in fuzz/artifacts/<target>/.
set -euo pipefail
cd "$(dirname "$0")/../fuzz"

seconds=${FUZZ_SECONDS:-30}
targets=(restore model_file csv push_solve)

if ! rustup run nightly rustc --version >/dev/null 2>&1; then
  echo "SKIP fuzz smoke: no nightly toolchain (rustup toolchain install nightly)"
  exit 0
fi
if ! cargo +nightly fuzz --version >/dev/null 2>&1; then
  echo "SKIP fuzz smoke: cargo-fuzz is not installed (cargo install cargo-fuzz)"
  exit 0
fi

for t in "${targets[@]}"; do
  mkdir -p "corpus/$t"
  # Work on a copy so that the smoke run does not grow the committed corpus.
  work=$(mktemp -d)
  cp -r "corpus/$t/." "$work/"
  echo "fuzz $t: ${seconds} s"
  # One process (libFuzzer's default without -jobs/-workers): the machine may be shared.
  set +e
  cargo +nightly fuzz run "$t" "$work" -- -max_total_time="$seconds" -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 >"$work.log" 2>&1
  status=$?
  set -e
  grep -E '^(stat::number_of_executed_units|Done|==[0-9]+==|SUMMARY)' "$work.log" || tail -20 "$work.log"
  rm -f "$work.log"
  rm -rf "$work"
  if [ "$status" -ne 0 ]; then
    echo "fuzz $t: FAILED (exit $status), input in fuzz/artifacts/$t/" >&2
    exit 1
  fi
done
echo "fuzz smoke: ${#targets[@]} targets ran ${seconds} s each without a crash or a hang"
