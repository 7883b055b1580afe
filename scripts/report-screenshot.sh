#!/bin/sh
# docs/report.png: the top of the HTML report of the README tour's first command (the example
# servo record), rendered by headless Chromium (Debian: apt-get install -y chromium).
# Usage: scripts/report-screenshot.sh   (HSID names the binary; default: the release build)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
if [ -z "${HSID:-}" ]; then
  cargo build --release -q -p hsid-host --bin hsid
  HSID=$root/target/release/hsid
fi
# Run as `hsid`, so that the page's command line reads as a user's.
case $HSID in */*) PATH=$(cd "$(dirname "$HSID")" && pwd):$PATH ;; esac
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
mkdir -p examples/data
cp "$root/examples/data/servo.csv" "$root/examples/data/servo-backlash.json" examples/data/
hsid identify --data examples/data/servo.csv --umin -1 --umax 1 --ts 0.01 \
  --input-unit V --output-unit deg --true-plant examples/data/servo-backlash.json \
  --out out/servo --html servo-report.html >/dev/null
chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
  --disable-background-networking --disable-component-update --disable-sync \
  --user-data-dir="$work/profile" --hide-scrollbars --window-size=1000,1500 \
  --screenshot="$root/docs/report.png" "file://$work/servo-report.html" 2>/dev/null
echo "wrote docs/report.png from $(wc -c < servo-report.html) bytes of HTML"
