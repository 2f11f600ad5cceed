#!/usr/bin/env bash
# Fuzzes what reads untrusted files (tests/fuzz/: libFuzzer + ASan + UBSan, clang-14), each target for
# a bounded time: tools/fuzz.sh [SECONDS] [TARGET...] (default 60 s each; targets scene_reader,
# mesh_reader, sweep_spec, report_reader, edit_log). Seeds: scene_reader the shipped scenes and the docs' JSON
# examples; mesh_reader the shipped meshes and tests/fuzz/seeds/mesh_reader/; sweep_spec the docs'
# JSON examples and tests/fuzz/seeds/sweep_spec/; report_reader tests/fuzz/seeds/report_reader/;
# edit_log the docs' JSON examples and tests/fuzz/seeds/edit_log/.
# The checked-in regressions of a target (tests/fuzz/regressions/TARGET/) run first and must pass.
# Exits non-zero on any finding; the input is left in build/fuzz/findings/TARGET/ (add it to the
# target's regressions once fixed). A fixed seed makes a run repeatable on one machine.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scene_reader mesh_reader sweep_spec report_reader edit_log)
build=build/fuzz
cmake -S tests/fuzz -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++-14 >/dev/null
cmake --build "$build" -j"$(nproc)" >/dev/null

# The docs' JSON examples: every ```json block, one file each.
docs_json() {
  awk -v dir="$1" '/^```json/ { n++; file = sprintf("%s/doc-%03d.json", dir, n); on = 1; next }
                   /^```/ { on = 0 } on { print > file }' docs/*.md
}

seed() {
  local target="$1" dir="$2"
  case "$target" in
    scene_reader) cp scenes/*.json "$dir"/; docs_json "$dir" ;;
    mesh_reader)
      for m in scenes/*.obj; do { printf 'o'; cat "$m"; } > "$dir/$(basename "$m")"; done ;;
    sweep_spec | edit_log) docs_json "$dir" ;;
  esac
  if [ -d "tests/fuzz/seeds/$target" ]; then cp tests/fuzz/seeds/"$target"/* "$dir"/; fi
}

for target in "${targets[@]}"; do
  binary="$build/fuzz_$target"
  [ -x "$binary" ] || { echo "fuzz: no target $target" >&2; exit 2; }
  seeds="$build/seeds/$target" findings="$build/findings/$target" corpus="$build/corpus/$target"
  rm -rf "$seeds" "$findings"
  mkdir -p "$seeds" "$findings" "$corpus"
  seed "$target" "$seeds"
  regressions="tests/fuzz/regressions/$target"
  if compgen -G "$regressions/*" >/dev/null; then
    "$binary" -runs=0 "$regressions"/* >/dev/null 2>"$build/$target.regressions.log" || {
      cat "$build/$target.regressions.log" >&2; echo "fuzz: $target: a regression input fails" >&2; exit 1; }
  fi
  max_len=65536
  [ "$target" != report_reader ] || max_len=262144  # two whole reports
  echo "fuzz: $target: $(ls "$seeds" | wc -l) seeds, ${seconds} s"
  # rss_limit: a refused huge input must not need gigabytes; timeout: nor seconds.
  "$binary" "$corpus" "$seeds" -seed=1 -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len="$max_len" \
    -artifact_prefix="$findings/" -print_final_stats=1 >"$build/$target.log" 2>&1 || {
    tail -n 40 "$build/$target.log" >&2
    echo "fuzz: $target: finding(s) in $findings/" >&2
    exit 1
  }
  grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb" "$build/$target.log" | sed "s/^/fuzz: $target: /"
done
