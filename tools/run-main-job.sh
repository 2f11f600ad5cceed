#!/usr/bin/env bash
# The main job from a fresh clone: install what is missing, build, and on the default device (the
# first GPU, else PoCL), for the drops scene: build its sparse bricks (leaf bricks of 0.0625) and BVH,
# ray trace them from the scene's camera and measure the picture against the reference tracer
# (`sdfbrick render --compare`), then evaluate a slice of its field against the host reference
# (`sdfbrick eval`). Leaves out/drops-normals.png (with -reference and -difference beside it),
# out/drops-render.json, out/drops-slice.png and out/drops-eval.json, and prints the summaries.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
cmake --preset release >/dev/null
cmake --build build/release -j"$(nproc)" --target sdfbrick
mkdir -p out
build/release/host/sdfbrick devices
build/release/host/sdfbrick render scenes/drops.json --brick-size 0.0625 --width 1280 --height 720 --compare \
    --out out/drops-normals.png --json out/drops-render.json
build/release/host/sdfbrick eval scenes/drops.json --out out/drops-slice.png --json out/drops-eval.json
