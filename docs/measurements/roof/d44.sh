#!/bin/bash
# d44: evaluation on NVIDIA: bin = 611105d (skip test inside the fold), bh = 4d0baa9 (skip records in
# local memory on every device), bn = records with CPU lanes only (one lane: the test inside the fold
# again); engraved_slab adaptive per kernel; PoCL 16 cores.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+' | head -9 | tr '\n' ' '; }
S=scenes/stability
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
.device/bn/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for r in 1 2; do
  for sc in "scenes/drops.json" "/tmp/sculpt_dense.json" "scenes/sculpt.json" "scenes/rain.json" "$S/ground_trees.json" "$S/steep_blends.json"; do
    for v in bin bh bn; do
      echo "$r $v $sc: $(timeout 60 .device/$v/sdfbrick -d gpu build $sc --brick-size 0.0625 $X 2>&1 | ev)"
    done
  done
done
echo "== adaptive engraved_slab E=0.002 and uniform 0.015625"
for v in bh bn; do echo "$v A: $(timeout 60 .device/$v/sdfbrick -d gpu build $S/engraved_slab.json --tolerance 0.002 $X 2>&1 | ev)"; done
echo "bn U: $(timeout 60 .device/bn/sdfbrick -d gpu build $S/engraved_slab.json --brick-size 0.015625 $X 2>&1 | ev)"
echo "== PoCL 16 cores"
for v in bh bn bh bn; do echo "pocl $v drops: $(timeout 100 .device/$v/sdfbrick -d cpu build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 3 2>&1 | ev)"; done
echo "== engraved_slab adaptive per kernel and level (bn)"
timeout 60 .device/bn/sdfbrick -d gpu build $S/engraved_slab.json --tolerance 0.002 $X --kernel-stats --json /tmp/ea.json 2>&1 | sed -n '/level  cell/,/edits per/p;/kernel  /,/digest/p' | cut -c1-120
python3 -c "
import json;d=json.load(open('/tmp/ea.json'))
for l in d['geometries'][0]['launches']:
    if l['device_ms']>0.01: print(l['kernel'], l['level'], l['stage'], l['global'], l['local'], round(l['device_ms'],4))" 2>&1 | head -60
