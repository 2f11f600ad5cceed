#!/bin/bash
# The evaluation's item test reading only the fields it needs from __local memory (k_new: field by
# field; k_vec: three float4 loads) against the kernels of HEAD (embedded), alternating, two rounds.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
B=.device/bnew/sdfbrick
ev() { grep -oE 'check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|^  digest [0-9a-f]+' | head -4 | tr '\n' ' '; }
$B scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for round in 1 2; do
  for sc in "scenes/drops.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "scenes/stability/steep_blends.json --brick-size 0.015625" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001" "scenes/stability/ground_trees.json --tolerance 0.002"; do
    for k in shipped k_new k_vec; do
      kd=""; [ $k != shipped ] && kd="--kernel-dir .device/$k"
      echo "$round $sc $k: $($B -d gpu $kd build $sc $X 2>&1 | ev)"
    done
  done
done
for k in shipped k_new; do
  kd=""; [ $k != shipped ] && kd="--kernel-dir .device/$k"
  echo "pocl drops $k: $(timeout 100 $B -d cpu $kd build scenes/drops.json --brick-size 0.0625 --lanes 1 2>&1 | ev)"
done
$B -d gpu --kernel-dir .device/k_new build scenes/drops.json --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E 'brick_evaluate'
