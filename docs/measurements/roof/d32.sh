#!/bin/bash
# The evaluation compiled with the folds of the geometry's primitives and operations alone (bnew)
# against HEAD's binary (bhead), alternating, two rounds, digests beside the times.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
ev() { grep -oE 'check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|^  digest [0-9a-f]+' | head -4 | tr '\n' ' '; }
.device/bnew/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
.device/bnew/sdfbrick scene generate stability/edits_65536 -o /tmp/edits_65536.json > /dev/null 2>&1
S=scenes/stability
for round in 1 2; do
  for sc in "scenes/drops.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" "/tmp/edits_65536.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "scenes/board.json --brick-size 0.03125" "scenes/gears.json" "$S/steep_blends.json --brick-size 0.015625" "$S/ground_trees.json --brick-size 0.015625" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001" "scenes/board.json --brick-size 0.03125 --tolerance 0.001" "$S/engraved_slab.json --tolerance 0.002" "$S/ground_trees.json --tolerance 0.002" "$S/steep_blends.json --tolerance 0.002"; do
    for v in bhead bnew; do
      echo "$round $sc $v: $(timeout 100 .device/$v/sdfbrick -d gpu build $sc $X 2>&1 | ev)"
    done
  done
done
for v in bhead bnew; do
  echo "pocl drops $v: $(timeout 100 .device/$v/sdfbrick -d cpu build scenes/drops.json --brick-size 0.0625 2>&1 | ev)"
  .device/$v/sdfbrick -d gpu build scenes/drops.json --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E 'brick_evaluate'
  .device/$v/sdfbrick -d gpu build /tmp/sculpt_dense.json --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E 'brick_evaluate'
done
