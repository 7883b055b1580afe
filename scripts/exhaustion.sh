#!/usr/bin/env bash
# Resource exhaustion on the host: time and peak resident memory (GNU time -v) of hsid on
#   1. a CSV of 10^8 rows (about 4 GB): `identify --stream` reads it row by row; `identify`
#      without --stream refuses it before reading;
#   2. a model file of 1 GB (sparse): refused before reading;
#   3. a directory of 10^5 checkpoints and one sparse file of 1 GB: `hsid fleet --states` on
#      all of them, and `ls` of it.
# Not run by CI (it writes gigabytes into a temporary directory, removed at the end, and takes
# tens of minutes); run it by hand after `cargo build --release -p hsid-host`.
# PARTS="csv model fleet" chooses the parts; ROWS and STATES scale the sizes down to try it.
set -euo pipefail
cd "$(dirname "$0")/.."
hsid=$PWD/target/release/hsid
parts=${PARTS:-csv model fleet}
rows=${ROWS:-100000000}
states=${STATES:-100000}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/hsid-exhaustion.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
# Elapsed time, peak memory and what the command said on stderr (its first lines).
peak() {
  /usr/bin/time -v "$@" 2>"$tmp/time.txt" >"$tmp/out.txt" || true
  grep -E 'Maximum resident|Elapsed' "$tmp/time.txt"
  { grep -v -E '^\s|Command exited' "$tmp/time.txt" || true; } | head -n 3 | cut -c1-400
  head -c 600 "$tmp/out.txt"
  echo
}

if [[ " $parts " == *" csv "* ]]; then
  # Simulated servo records of 10^6 samples, each with its own seeds (excitation and noise):
  # a hold of 300 at u_min, Table I, and 300 samples at u_min at the end where the plant comes
  # to rest; joined (rows below the header) until the file has $rows data rows. Each starts
  # at rest where the one before ended, so the joined record is one the servo could give.
  # (Copies of one record would not do: their noise repeats, and the automatic order reads
  # the repetition as dynamics.)
  block=$((rows < 1000000 ? rows : 1000000))
  for seed in $(seq 1 $((rows / block))); do
    { "$hsid" excite --umin -1 --umax 1 --samples $((block - 300)) --hold 300 --seed "$seed"
      for _ in $(seq 1 300); do echo -1; done; } |
      "$hsid" simulate --plant examples/data/servo-backlash.json --input - --seed "$seed" |
      grep -v '^#' >"$tmp/block.csv"
    if [ "$seed" -eq 1 ]; then sed -n 1p "$tmp/block.csv" >"$tmp/big.csv"; fi
    tail -n +2 "$tmp/block.csv" >>"$tmp/big.csv"
  done
  rm -f "$tmp/block.csv"
  echo "== CSV of $(($(wc -l <"$tmp/big.csv") - 1)) rows, $(stat -c %s "$tmp/big.csv") bytes"
  # The order fixed at the servo's 2, so that its poles can be compared with the truth.
  args=(--data "$tmp/big.csv" --umin -1 --umax 1 --segments 7 --f 10 --p 10 --hold 300 --order 2)
  echo "-- identify (whole record, subspace only): refused before reading if over 256 MiB"
  peak "$hsid" identify "${args[@]}" --no-refine
  echo "-- identify --stream: row by row"
  peak "$hsid" identify "${args[@]}" --stream --json "$tmp/big.json"
  rm -f "$tmp/big.csv"
fi

if [[ " $parts " == *" model "* ]]; then
  echo "== model file of 1 GB (sparse): refused before reading"
  truncate -s 1G "$tmp/big.json"
  peak "$hsid" validate --model "$tmp/big.json" --data examples/data/servo-check.csv
  rm -f "$tmp/big.json"
fi

if [[ " $parts " == *" fleet "* ]]; then
  # One device's weekly checkpoints from the simulated fleet, copied to $states files.
  "$hsid" fleet simulate --devices 1 --weeks 1 --out "$tmp/one" --truth "$tmp/truth.csv" \
    >/dev/null
  state=$(find "$tmp/one" -type f | head -n 1)
  echo "== directory of $states checkpoints of $(stat -c %s "$state") bytes"
  mkdir "$tmp/states"
  (cd "$tmp/states" && seq -f "dev%06g.bin" 1 "$states" | xargs -n 1000 sh -c \
    'for f; do cp "$0" "$f"; done' "$state")
  # One file of 1 GB (sparse) among them: refused by its size, unread.
  truncate -s 1G "$tmp/states/dev000000-big.bin"
  echo "-- ls -f (listing only)"
  peak ls -f "$tmp/states"
  echo "-- hsid fleet --states (list, read and solve each, one thread)"
  peak "$hsid" fleet --states "$tmp/states" --out "$tmp/models.jsonl" --threads 1
  echo "models: $(wc -l <"$tmp/models.jsonl") lines, $(stat -c %s "$tmp/models.jsonl") bytes"
  head -n 1 "$tmp/models.jsonl" | cut -c1-400
fi
