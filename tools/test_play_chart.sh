#!/usr/bin/env bash
# Runs tools/play_chart.py on tests/data/play_sample.json (a real `sdfbrick play --json` report of
# drops on PoCL) and checks that the PNG is written and non-empty; then that a report that is not a
# play report is refused. Exits non-zero on any failure.
set -euo pipefail
cd "$(dirname "$0")/.."
py=/usr/bin/python3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
$py tools/play_chart.py tests/data/play_sample.json tests/data/play_sample.json --out "$tmp/play.png" --title sample
[[ -s $tmp/play.png ]] || { echo "FAIL: no chart"; exit 1; }
[[ $(head -c 8 "$tmp/play.png" | od -An -c | tr -d ' ') == '211PNG\r\n032\n' ]] || { echo "FAIL: not a PNG"; exit 1; }
echo '{"command": "build"}' > "$tmp/build.json"
if $py tools/play_chart.py "$tmp/build.json" --out "$tmp/bad.png" 2>"$tmp/err"; then
    echo "FAIL: a build report was charted"; exit 1
fi
grep -q "not a play report" "$tmp/err" || { echo "FAIL: refusal: $(cat "$tmp/err")"; exit 1; }
[[ ! -e $tmp/bad.png ]] || { echo "FAIL: a chart was written for a refused report"; exit 1; }
echo "play chart: ok"
