#!/bin/bash
# d74: main (3777b12's binary with its kernels, ks) with the evaluation in one lane against lanes of
# 2 (`--lanes 2`, which puts the count's children and the check in lanes too), on the scenes d73 did
# not try; one alternation, 10 captures. Prepared, not run: the session's device time was spent.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
X="--warmup 1 --repeat 10"
S=scenes/stability
B=.device/bin/sdfbrick-new
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|^  digest [0-9a-f]+' | head -10 | tr '\n' ' '; }
for c in "scenes/rubble.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625" \
         "$S/ground_trees.json --brick-size 0.0625" "scenes/board.json --brick-size 0.03125" "$S/engraved_slab.json --brick-size 0.0625" \
         "$S/edits_65536.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "scenes/drops.json --brick-size 0.0625"; do
  for l in 1 2; do echo "lanes $l $c: $(timeout 30 $B -d gpu --kernel-dir .device/ks build $c $X --lanes $l 2>&1 | ev)"; done
done
