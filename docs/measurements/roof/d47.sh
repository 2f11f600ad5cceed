#!/bin/bash
# d47: brick_check's work-group on GPUs (CHECKG, an override of this build only: 64, 128, 256).
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
ev() { grep -oE 'check [0-9.]+|total [0-9.]+ ms|^  digest [0-9a-f]+' | head -3 | tr '\n' ' '; }
S=scenes/stability
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
for sc in "$S/engraved_slab.json --tolerance 0.002" "scenes/board.json --brick-size 0.03125 --tolerance 0.001" "$S/grooved_board.json --tolerance 0.002" "$S/steep_blends.json --tolerance 0.002" "$S/ground_trees.json --tolerance 0.002" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001"; do
  for g in 128 64 256 128 64; do
    echo "CHECKG=$g $sc: $(CHECKG=$g timeout 60 .device/bm/sdfbrick -d gpu build $sc $X 2>&1 | ev)"
  done
done
