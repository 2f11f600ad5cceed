#!/bin/bash
# d75: the adaptive check folding per part of the cell (new binary sdfbrick-chk with its kernels kc,
# `--check-split 1, 2, 3`) against main's (sdfbrick-new, kernels ks), beside the uniform builds at the
# finest size; two rounds, 10 captures. Then d74's question: the evaluation in one lane against lanes
# of 2 (`--lanes 2`) on the other scenes, and drops in lanes of 2 at other work-group sizes; last, on
# an H200 only, the full search of the one-lane evaluation's chunk, group and register cap.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
GPU=$(nvidia-smi --query-gpu=name --format=csv,noheader)
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
X="--warmup 1 --repeat 10"
S=scenes/stability
OLD=".device/bin/sdfbrick-new -d gpu --kernel-dir .device/ks"
NEW=".device/bin/sdfbrick-chk -d gpu --kernel-dir .device/kc"
ev() { grep -oE 'tuning: .*|edits per leaf: mean [0-9.]+|count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|^  digest [0-9a-f]+|leaves: [0-9]+|[0-9]+ leaf bricks' | head -12 | tr '\n' ' '; }
for r in 1 2; do
  for c in "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "$S/engraved_slab.json --tolerance 0.002" \
           "scenes/board.json --brick-size 0.03125 --tolerance 0.001" "$S/grooved_board.json --tolerance 0.002" \
           "$S/steep_blends.json --tolerance 0.002" "$S/ground_trees.json --tolerance 0.002" \
           "scenes/drops.json --brick-size 0.03125 --tolerance 0.001"; do
    echo "$r old $c: $(timeout 40 $OLD build $c $X 2>&1 | ev)"
    for k in 1 2 3; do echo "$r split $k $c: $(timeout 40 $NEW build $c $X --check-split $k 2>&1 | ev)"; done
  done
  for c in "$S/engraved_slab.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.015625" "scenes/board.json --brick-size 0.03125"; do
    echo "$r uniform $c: $(timeout 40 $NEW build $c $X 2>&1 | ev)"
  done
done
for c in "scenes/rubble.json" "scenes/rain.json" "scenes/sculpt.json" "$S/ground_trees.json" "$S/engraved_slab.json" \
         "$S/edits_65536.json" "scenes/drops.json"; do
  for l in 1 2; do echo "lanes $l $c: $(timeout 40 $OLD build $c --brick-size 0.0625 $X --lanes $l 2>&1 | ev)"; done
done
for g in "--group 32" "--group 128" "--group 64 --chunk 16"; do
  echo "lanes 2 $g drops: $(timeout 40 $OLD build scenes/drops.json --brick-size 0.0625 $X --lanes 2 $g 2>&1 | ev)"
done
echo "elapsed $SECONDS s"
case "$GPU" in *H200*)
  $OLD scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
  timeout $((585 - SECONDS)) $OLD --tuning-db /tmp/tuned.json tune scenes/drops.json scenes/rubble.json \
    /tmp/sculpt_dense.json --brick-size 0.0625 --kernels evaluate --strategy full --repeat 3 --warmup 1 --json $OUT/d75-tune.json 2>&1 | tail -25;;
esac
