#!/usr/bin/env bash
# The main job from a fresh clone: install what is missing, build, and run `sdfbrick eval` on the
# default device (the first GPU, else PoCL) for the drops scene. Leaves out/drops-slice.png and
# out/drops-eval.json, and prints the summary.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
cmake --preset release >/dev/null
cmake --build build/release -j"$(nproc)" --target sdfbrick
mkdir -p out
build/release/host/sdfbrick devices
build/release/host/sdfbrick eval scenes/drops.json --out out/drops-slice.png --json out/drops-eval.json
