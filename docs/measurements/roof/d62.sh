#!/bin/bash
# Not run: no device time was left in the session that wrote it (2026-12-07).
# d62: the H100's old compiled-in evaluation entry (chunk 16, group 64) against the three-scene search's
# (chunk 32, group 64, registers 56) on the scenes the search did not see: short lists (rain, board,
# ground_trees), adaptive builds; given as flags so that either card measures both; one round of 10
# captures. Then engraved_slab at E = 0.002 against uniform 0.015625, per level.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
X="--warmup 1 --repeat 10"
S=scenes/stability
ev() { grep -oE 'count [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+' | head -8 | tr '\n' ' '; }
for r in 1; do
  for c in "scenes/rain.json --brick-size 0.0625" "scenes/board.json --brick-size 0.03125" "$S/ground_trees.json --brick-size 0.015625" \
           "$S/engraved_slab.json --tolerance 0.002" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001"; do
    for a in "--chunk 16 --group 64" "--chunk 32 --group 64 --eval-max-registers 56"; do
      echo "$r $c [$a]: $(timeout 60 .device/bn/sdfbrick -d gpu build $c $a $X 2>&1 | ev)"
    done
  done
done
for t in "--tolerance 0.002"; do echo "== engraved $t per level"; timeout 60 .device/bn/sdfbrick -d gpu build $S/engraved_slab.json $t $X --kernel-stats 2>&1 | grep -E "stages|^  [a-z_]+ +[a-z,]+ +[0-9]+ |^    level|digest"; done
