#!/bin/bash
# d77: main with the evaluation branching once per edit on every list (3c1798e's binary, kernels ks):
# adaptive builds against uniform ones at their finest size, one round of 10 captures (device and
# wall ms, leaves, digests). Prepared, not run: the session's device time went to starts that got
# no machine.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
X="--warmup 1 --repeat 10"
S=scenes/stability
B=".device/bin/sdfbrick-new -d gpu --kernel-dir .device/ks"
ev() { grep -oE '^  geometry [^:]+: [0-9]+ leaf bricks|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+' | head -7 | tr '\n' ' '; }
for c in "$S/ground_trees.json" "$S/engraved_slab.json" "$S/grooved_board.json" "$S/steep_blends.json"; do
  echo "uniform 0.015625 $c: $(timeout 30 $B build $c --brick-size 0.015625 $X 2>&1 | ev)"
  echo "adaptive E 0.002 $c: $(timeout 30 $B build $c --tolerance 0.002 $X 2>&1 | ev)"
done
for c in "scenes/drops.json --brick-size 0.03125" "scenes/board.json --brick-size 0.03125" "$S/engraved_slab.json --brick-size 0.0625"; do
  echo "uniform $c: $(timeout 30 $B build $c $X 2>&1 | ev)"
done
for c in "scenes/drops.json --brick-size 0.03125 --tolerance 0.001" "scenes/board.json --brick-size 0.03125 --tolerance 0.001" \
         "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008"; do
  echo "adaptive $c: $(timeout 30 $B build $c $X 2>&1 | ev)"
done
echo "elapsed $SECONDS s"
