#!/bin/bash
# A fresh tuning search of brick_evaluate on the GPU (it ran on an H200) (drops 0.0625, every candidate: chunk x group x
# register cap), then the builtin entry (chunk 16, group 64, no cap) against the tuned values on
# several scenes, two rounds of 10 captures, alternating.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
B=.device/bnew/sdfbrick
X="--warmup 1 --repeat 10"
ev() { grep -oE 'tuning: [^(]*|count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|^  digest [0-9a-f]+' | head -7 | tr '\n' ' '; }
$B scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
$B -d gpu --tuning-db /tmp/tuned.json tune scenes/drops.json --brick-size 0.0625 --kernels evaluate --strategy full \
  --budget 200 --repeat 5 --json $OUT/tune-h100.json  # saved as d40-tune-h200.json: the card lent was an H200 2>&1 | tail -25
S=scenes/stability
for round in 1 2; do
  for sc in "scenes/drops.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" "$S/edits_65536.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "scenes/board.json --brick-size 0.03125" "$S/ground_trees.json --brick-size 0.015625" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001" "$S/engraved_slab.json --tolerance 0.002"; do
    echo "$round $sc builtin: $(timeout 100 $B -d gpu build $sc $X 2>&1 | ev)"
    echo "$round $sc tuned: $(timeout 100 $B -d gpu --tuning-db /tmp/tuned.json build $sc $X 2>&1 | ev)"
  done
done
cp /tmp/tuned.json $OUT/tuned-db.json
