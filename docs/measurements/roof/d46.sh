#!/bin/bash
# d46: the last checked level's minimum child count (MINC, an override of this build only) on the
# adaptive hard cases, NVIDIA; bm = 1c907e1 + the override.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|[0-9]+ leaf bricks of [0-9.]+|^  digest [0-9a-f]+' | head -9 | tr '\n' ' '; }
S=scenes/stability
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
for sc in "$S/engraved_slab.json --tolerance 0.002" "scenes/board.json --brick-size 0.03125 --tolerance 0.001" "$S/grooved_board.json --tolerance 0.002" "$S/steep_blends.json --tolerance 0.002" "$S/ground_trees.json --tolerance 0.002"; do
  for m in 2 4 8 16 2; do
    echo "MINC=$m $sc: $(MINC=$m timeout 60 .device/bm/sdfbrick -d gpu build $sc $X 2>&1 | ev)"
  done
done
