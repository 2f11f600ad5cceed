#!/usr/bin/env bash
# Fuzzes the scene reader (fuzz/scene_reader.cpp, libFuzzer + ASan + UBSan, clang-14) for a bounded
# time: tools/fuzz-scene.sh [SECONDS] (default 60). The seed corpus is scenes/*.json, the JSON
# examples of docs/, and the checked-in regressions in fuzz/regressions/ (each one is run first).
# Exits non-zero on any finding; the crashing input is left in build/fuzz/findings/ (add it to
# fuzz/regressions/ once fixed). Works in build/fuzz; needs clang-14 and libfuzzer-14-dev.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
build=build/fuzz
cmake -S fuzz -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++-14 >/dev/null
cmake --build "$build" -j"$(nproc)" >/dev/null
target="$build/fuzz_scene_reader"

seeds="$build/seeds"
rm -rf "$seeds" "$build/findings"
mkdir -p "$seeds" "$build/findings" "$build/corpus"
cp scenes/*.json fuzz/regressions/* "$seeds"/ 2>/dev/null || true
# The docs' JSON examples: every ```json block.
awk -v dir="$seeds" '/^```json/ { n++; file = sprintf("%s/doc-%03d.json", dir, n); on = 1; next }
                     /^```/ { on = 0 } on { print > file }' docs/*.md

# The regressions first: each must pass on its own.
if compgen -G "fuzz/regressions/*" >/dev/null; then
  "$target" -runs=0 fuzz/regressions/* >/dev/null 2>"$build/regressions.log" || {
    cat "$build/regressions.log" >&2; echo "fuzz-scene: a regression input fails" >&2; exit 1; }
fi
echo "fuzz-scene: $(ls "$seeds" | wc -l) seeds, ${seconds} s"
# rss_limit: a refused huge input must not need gigabytes; timeout: nor seconds.
"$target" "$build/corpus" "$seeds" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
  -artifact_prefix="$build/findings/" -print_final_stats=1 >"$build/fuzz.log" 2>&1 || {
  tail -n 40 "$build/fuzz.log" >&2
  echo "fuzz-scene: finding(s) in $build/findings/" >&2
  exit 1
}
grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb" "$build/fuzz.log" | sed 's/^/fuzz-scene: /'
grep -E "^#[0-9]+.*(DONE|cov:)" "$build/fuzz.log" | tail -n 1 | sed 's/^/fuzz-scene: /'
