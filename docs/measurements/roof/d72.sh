#!/bin/bash
# d72: main before this session (518e082: sdfbrick with kk) against main after it (3777b12:
# sdfbrick-new with ks, d70's kn prologue and the popcount scan), alternating, two rounds of 10
# captures, on whichever card the tool lent (printed first).
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
X="--warmup 1 --repeat 10"
S=scenes/stability
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+.*' | head -10 | tr '\n' ' '; }
.device/bin/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for r in 1 2; do
  for c in "scenes/drops.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" \
           "scenes/sculpt.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "scenes/board.json --brick-size 0.03125" \
           "$S/edits_65536.json --brick-size 0.0625" "$S/ground_trees.json --brick-size 0.0625" \
           "$S/engraved_slab.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" \
           "scenes/drops.json --brick-size 0.03125 --tolerance 0.001"; do
    echo "$r old $c: $(timeout 40 .device/bin/sdfbrick -d gpu --kernel-dir .device/kk build $c $X 2>&1 | ev)"
    echo "$r new $c: $(timeout 40 .device/bin/sdfbrick-new -d gpu --kernel-dir .device/ks build $c $X 2>&1 | ev)"
  done
done
