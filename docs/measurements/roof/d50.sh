#!/bin/bash
# d50: brick samples numbered in 4 x 4 x 4 cubes (kn) against the numbering before (ko), both
# loaded with --kernel-dir into the 1c907e1 binary (bn); NVIDIA, alternating, two rounds.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|[0-9]+ leaf bricks of [0-9.]+|^  digest [0-9a-f]+' | head -10 | tr '\n' ' '; }
S=scenes/stability
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
.device/bn/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for sc in "scenes/drops.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625" "$S/ground_trees.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "$S/engraved_slab.json --tolerance 0.002" "scenes/board.json --brick-size 0.03125 --tolerance 0.001" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001"; do
  for v in ko kn ko kn; do
    echo "$v $sc: $(timeout 60 .device/bn/sdfbrick -d gpu --kernel-dir .device/$v build $sc $X 2>&1 | ev)"
  done
done
