#!/bin/sh
# The README quick start's example records, made by hsid itself: a servo with gearbox backlash
# (servo-backlash.json: a play of 0.2 V, a 3 Hz second-order plant with damping 0.4, sampled at
# 100 Hz, white output noise at 20 dB) driven by the Table I excitation on [-1, 1] V:
#   servo.csv        estimation record, excitation seed 1, noise seed 1
#   servo-check.csv  validation record, excitation seed 2, noise seed 2
# Usage: make-servo-records.sh [OUTDIR]   (default: this folder; HSID names the binary)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-$here}
hsid=${HSID:-hsid}
for pair in "servo 1" "servo-check 2"; do
  set -- $pair
  "$hsid" excite --umin -1 --umax 1 --samples 6300 --hold 300 --seed "$2" \
    | "$hsid" simulate --plant "$here/servo-backlash.json" --input - --seed "$2" > "$out/$1.csv"
done
