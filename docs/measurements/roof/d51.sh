#!/bin/bash
# d51: the evaluation's folds without the products of edits whose scales are 1 (kn) against the
# kernels before (ko, 2e34ee1), both loaded with --kernel-dir into the 1c907e1 binary (bn);
# NVIDIA alternating, two rounds; PoCL 16 cores, two rounds.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|[0-9]+ leaf bricks of [0-9.]+|^  digest [0-9a-f]+' | head -10 | tr '\n' ' '; }
S=scenes/stability
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
.device/bn/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for sc in "scenes/drops.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625" "$S/ground_trees.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "$S/engraved_slab.json --tolerance 0.002" "$S/engraved_slab.json --brick-size 0.015625" "scenes/board.json --brick-size 0.03125 --tolerance 0.001" "scenes/board.json --brick-size 0.03125" "$S/grooved_board.json --tolerance 0.002" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001"; do
  for v in ko kn ko kn; do
    echo "$v $sc: $(timeout 60 .device/bn/sdfbrick -d gpu --kernel-dir .device/$v build $sc $X 2>&1 | ev)"
  done
done
for sc in "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "scenes/rubble.json --brick-size 0.125" "scenes/drops.json --brick-size 0.0625"; do
  for v in ko kn ko kn; do
    echo "pocl $v $sc: $(timeout 100 .device/bn/sdfbrick -d cpu --kernel-dir .device/$v build $sc --warmup 1 --repeat 3 2>&1 | ev)"
  done
done
