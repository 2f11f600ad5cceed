#!/usr/bin/env bash
# The CI performance gate (docs/ci-gate.md): builds and renders scenes/spheres on PoCL with the
# release binary and gates the reports against the baselines kept in tests/data/gate/ with
# `sdfbrick compare --gate default`. Writes a Markdown summary, JUnit XML and the JSON verdict of
# each gate into OUT (default build/release/gate). Exit status: 0 pass, 2 bad input, 3 regression
# (the larger of the two gates').
#
#   tools/ci-gate.sh [OUT]          gate this build against the baselines
#   tools/ci-gate.sh --refresh      write this build's reports as the new baselines (then commit them)
#
# $SDFBRICK: the binary (default build/release/host/sdfbrick); $SDFBRICK_DEVICE: the device (default
# cpu, PoCL). No tuning database is read (--no-tuning): every machine runs the built-in defaults.
set -euo pipefail
cd "$(dirname "$0")/.."
sdfbrick=${SDFBRICK:-build/release/host/sdfbrick}
baselines=tests/data/gate
refresh=0
if [ "${1:-}" = "--refresh" ]; then
    refresh=1
    shift
fi
out=${1:-build/release/gate}
mkdir -p "$out"
export SDFBRICK_DEVICE=${SDFBRICK_DEVICE:-cpu}
export SDFBRICK_CACHE_DIR=${SDFBRICK_CACHE_DIR:-build/release/kernel-cache}
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-build/release/pocl-cache}

# The reports: a build at the default brick size and a render --compare at 160 x 90 (both one
# capture: times are not gated against a baseline from another machine, only the deterministic figures).
reports=$out
[ "$refresh" = 1 ] && reports=$baselines
"$sdfbrick" --no-tuning build scenes/spheres.json --json "$reports/spheres-build.json" >"$out/build.txt"
"$sdfbrick" --no-tuning render scenes/spheres.json --compare --width 160 --height 90 \
    --out "$out/spheres.ppm" --json "$reports/spheres-render.json" >"$out/render.txt"
if [ "$refresh" = 1 ]; then
    echo "ci-gate: new baselines in $baselines/ (spheres-build.json, spheres-render.json); commit them"
    exit 0
fi

status=0
for kind in build render; do
    rc=0
    "$sdfbrick" compare "$baselines/spheres-$kind.json" "$out/spheres-$kind.json" --gate default \
        --summary "$out/gate-$kind.md" --junit "$out/gate-$kind.xml" --json "$out/gate-$kind.json" || rc=$?
    [ "$rc" -gt "$status" ] && status=$rc
done
echo "ci-gate: summaries in $out/gate-build.md and $out/gate-render.md (status $status)"
exit "$status"
