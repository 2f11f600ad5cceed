#!/bin/bash
# d64: d63's binary and variants ko (3c5a36f's kernels) and kn (fma) against kz: kn with the
# work-item's skip test for the other primitives compiled per primitive (FOLD_NEAR), the extremes
# kept in CPU lanes only; alternating, two rounds of 10 captures.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
X="--warmup 1 --repeat 10"
S=scenes/stability
B=.device/bin/sdfbrick
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+.*' | head -10 | tr '\n' ' '; }
$B scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for r in 1 2; do
  for c in "scenes/drops.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" \
           "scenes/sculpt.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "scenes/board.json --brick-size 0.03125" \
           "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "$S/engraved_slab.json --brick-size 0.0625" \
           "$S/ground_trees.json --brick-size 0.0625" "$S/edits_65536.json --brick-size 0.0625"; do
    for k in ko kn kz; do echo "$r $k $c: $(timeout 40 $B -d gpu --kernel-dir .device/$k build $c $X 2>&1 | ev)"; done
  done
done
for d in gpu cpu; do for sc in scenes/rubble.json scenes/board.json; do
  echo "$d kz $sc 0.125: $(timeout 60 $B -d $d --kernel-dir .device/kz build $sc --brick-size 0.125 2>&1 | grep -oE 'digest [0-9a-f]+.*')"; done; done
# Then a full search of the evaluation's chunk, group and register cap with kz over drops, rubble and
# sculpt_dense (as d60), for the H100's compiled-in entry.
timeout 300 $B -d gpu --kernel-dir .device/kz --tuning-db /tmp/tuned.json tune scenes/drops.json scenes/rubble.json \
  /tmp/sculpt_dense.json --brick-size 0.0625 --kernels evaluate --strategy full --repeat 3 --warmup 1 --json $OUT/d64-tune.json
