#!/bin/bash
# d73: ks (main, 3777b12) against kt: ks whose per-value fold of a sphere or capsule edit computes
# both results and selects (no branch per value, so the values' folds can interleave); same digests
# on PoCL here with --lanes 1. Alternating, two rounds of 10 captures; then drops in lanes of 2.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
X="--warmup 1 --repeat 10"
S=scenes/stability
B=.device/bin/sdfbrick-new
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+.*' | head -10 | tr '\n' ' '; }
$B scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for r in 1 2; do
  for c in "scenes/drops.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" \
           "scenes/sculpt.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "$S/ground_trees.json --brick-size 0.0625" \
           "scenes/drops.json --brick-size 0.03125 --tolerance 0.001"; do
    for k in ks kt; do echo "$r $k $c: $(timeout 40 $B -d gpu --kernel-dir .device/$k build $c $X 2>&1 | ev)"; done
  done
done
for l in 1 2; do echo "lanes $l ks drops: $(timeout 40 $B -d gpu --kernel-dir .device/ks build scenes/drops.json --brick-size 0.0625 $X --lanes $l 2>&1 | ev)"; done
for sc in drops rubble rain sculpt; do
  echo "gpu kt $sc 0.125: $(timeout 60 $B -d gpu --kernel-dir .device/kt build scenes/$sc.json --brick-size 0.125 2>&1 | grep -oE 'digest [0-9a-f]+.*')"; done
