#!/usr/bin/env bash
# Construction time against brick count over leaf sizes, for the power-law fit of
# tools/level_scaling.py. usage: bench/level_scaling.sh SDFBRICK DEVICE OUTDIR [SCENE...]
# Writes OUTDIR/SCENE-LEAF.json (`build --repeat $REPEAT --warmup 1`, REPEAT 5 unless set) for leaf
# sizes 0.25 .. 0.015625.
set -euo pipefail
bin=$1 device=$2 out=$3
shift 3
[ $# -gt 0 ] && scenes=("$@") || scenes=(cubes board)
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
for scene in "${scenes[@]}"; do
  for leaf in 0.25 0.125 0.0625 0.03125 0.015625; do
    "$bin" -d "$device" build "$here/scenes/$scene.json" --brick-size "$leaf" --repeat "${REPEAT:-5}" --warmup 1 \
      --json "$out/$scene-$leaf.json" > /dev/null
    echo "level_scaling: $scene $leaf done" >&2
  done
done
