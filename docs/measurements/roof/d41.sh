#!/bin/bash
# The sibling cull wherever a level's parents have 8 new children or more on average (cull_siblings
# as children per parent again; a parent's words shared by up to 256 work-groups, as fill the
# device), on GPUs with lists of 256 edits or more (bnew), against 2d88ebc (bhead: and 2 parents or
# more per compute unit, up to 64 work-groups a parent), alternating, two rounds of 10 captures.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
ev() { grep -oE 'check [0-9.]+|count [0-9.]+|cull [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|^  digest [0-9a-f]+' | head -6 | tr '\n' ' '; }
B=.device/bnew/sdfbrick
$B scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
S=scenes/stability
for round in 1 2; do
  for sc in "/tmp/sculpt_dense.json --brick-size 0.0625" "$S/edits_65536.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625" "scenes/drops.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "scenes/board.json --brick-size 0.03125" "$S/ground_trees.json --brick-size 0.015625" "$S/engraved_slab.json --brick-size 0.015625" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001" "$S/engraved_slab.json --tolerance 0.002"; do
    for v in bhead bnew; do
      echo "$round $sc $v: $(timeout 100 .device/$v/sdfbrick -d gpu build $sc $X 2>&1 | ev)"
    done
  done
done
for sc in /tmp/sculpt_dense.json $S/edits_65536.json; do
  echo "== bnew $sc"
  timeout 100 $B -d gpu build $sc --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E '^ +[0-9] |cull_mark'
done
