#!/usr/bin/env bash
# Long records: the default `hsid identify` (and optionally `hsid diagnose`) on the tour's servo
# driven for 10^4, 10^5 and 10^6 samples (`hsid excite | hsid simulate`, seed 1), wall time,
# CPU time and peak memory of each run, and the stages with the time each began (the progress
# lines). The numbers of docs/long-records.md come from this script on a quiet 2-core machine.
#
# Usage: scripts/long-records.sh [OUTDIR]   (default: target/long-records)
#   HSID       the binary (default: target/release/hsid, built when missing)
#   SIZES      the record lengths (default: "10000 100000 1000000")
#   DIAGNOSE   also time the default diagnose at these lengths (e.g. DIAGNOSE="100000")
#   FIXED      also time identify with the settings the default chose, given (default: 1)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-target/long-records}
mkdir -p "$out"
hsid=${HSID:-target/release/hsid}
if [ -z "${HSID:-}" ] && [ ! -x "$hsid" ]; then
  cargo build --release --quiet -p hsid-host --bin hsid
fi
plant=examples/data/servo-backlash.json
sizes=${SIZES:-"10000 100000 1000000"}

# Runs "$@", its stderr (the stages, one line each, as on a pipe) to $out/$name.stages;
# prints "wall s, CPU s, peak MB".
timed() {
  local name=$1
  shift
  /usr/bin/time -f '%e %U %S %M' -o "$out/$name.time" "$@" >"$out/$name.out" 2>"$out/$name.stages"
  awk '{ printf "%.1f s wall, %.1f s CPU, %.0f MB peak\n", $1, $2 + $3, $4 / 1024 }' "$out/$name.time"
}

for n in $sizes; do
  record=$out/servo-$n.csv
  [ -s "$record" ] || "$hsid" excite --umin -1 --umax 1 --samples "$n" --hold 300 --seed 1 \
    | "$hsid" simulate --plant "$plant" --input - --seed 1 >"$record"
  echo "== $n samples ($(du -h "$record" | cut -f1) of CSV)"
  printf 'identify, defaults: '
  timed "identify-$n" "$hsid" identify --data "$record" --umin -1 --umax 1 --json "$out/model-$n.json"
  grep -E '^(segments per path|order [0-9]+ chosen|choices made|horizons)' "$out/identify-$n.out" || true
  if [ "${FIXED:-1}" = 1 ]; then
    read -r segments order f p < <(python3 - "$out/model-$n.json" <<'EOF'
import json, sys
m = json.load(open(sys.argv[1]))
print(len(m["knots_asc"]) - 1, m["order"], m["f"], m["p"])
EOF
    )
    printf 'identify, those settings given (--segments %s --order %s --f %s --p %s): ' \
      "$segments" "$order" "$f" "$p"
    timed "fixed-$n" "$hsid" identify --data "$record" --umin -1 --umax 1 --segments "$segments" \
      --order "$order" --f "$f" --p "$p"
  fi
  for d in ${DIAGNOSE:-}; do
    [ "$d" = "$n" ] || continue
    printf 'diagnose, defaults: '
    timed "diagnose-$n" "$hsid" diagnose --data "$record" --umin -1 --umax 1
  done
done
echo "stages of each run (time each began): $out/*.stages"
