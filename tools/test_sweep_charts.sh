#!/usr/bin/env bash
# Runs tools/sweep_charts.py on the synthetic tests/data/sweep_sample.csv (2 scenes x 2 devices) and
# checks that every expected chart and the page are written, non-empty and linked from the page;
# then the same data split into one CSV per device, and that a missing file or a CSV without the
# parameter columns is refused. Exits non-zero on any failure.
set -euo pipefail
cd "$(dirname "$0")/.."
py=/usr/bin/python3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
check() {  # check DIR: every expected file exists, is non-empty, and every PNG is linked from index.md
    local f
    [[ -s $1/index.md ]] || { echo "FAIL: $1/index.md missing or empty"; failures=$((failures + 1)); return; }
    for scene in synthetic-spheres synthetic-fractal; do
        local files=("speed_accuracy_$scene.png" "build_vs_bricks_$scene.png" "vendors_$scene.png")
        for device in synthetic-gpu-a synthetic-cpu-b-pocl-like; do
            files+=("stages_${scene}_$device.png" "evaluate_chunk_${scene}_$device.png")
        done
        for f in "${files[@]}"; do
            if [[ ! -s $1/$f ]]; then
                echo "FAIL: $1/$f missing or empty"; failures=$((failures + 1))
            elif ! grep -qF "($f)" "$1/index.md"; then
                echo "FAIL: $f not linked from $1/index.md"; failures=$((failures + 1))
            fi
        done
    done
}

$py tools/sweep_charts.py tests/data/sweep_sample.csv --out "$tmp/one" --title "synthetic sample"
check "$tmp/one"
grep -q "Failed rows (2)" "$tmp/one/index.md" || { echo "FAIL: failed rows not listed"; failures=$((failures + 1)); }

# One CSV per device, concatenated by the script: the same charts.
head -1 tests/data/sweep_sample.csv | tee "$tmp/a.csv" > "$tmp/b.csv"
grep "Synthetic GPU A" tests/data/sweep_sample.csv >> "$tmp/a.csv"
grep "Synthetic CPU B" tests/data/sweep_sample.csv >> "$tmp/b.csv"
$py tools/sweep_charts.py "$tmp/a.csv" "$tmp/b.csv" --out "$tmp/two" > /dev/null
check "$tmp/two"

# Bad inputs must exit non-zero.
printf 'name,value\nx,1\n' > "$tmp/bad.csv"
for bad in "$tmp/no-such-file.csv" "$tmp/bad.csv"; do
    if $py tools/sweep_charts.py "$bad" --out "$tmp/bad" 2> "$tmp/err"; then
        echo "FAIL: $bad accepted"; failures=$((failures + 1))
    else
        echo "refused as expected: $(cat "$tmp/err")"
    fi
done

if ((failures)); then
    echo "test_sweep_charts: $failures failure(s)"
    exit 1
fi
echo "test_sweep_charts: ok"
