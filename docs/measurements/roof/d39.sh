#!/bin/bash
# The sibling cull splitting a parent's words over as many work-groups as fill the device (bnew) against
# bdf22bb (bhead), alternating, two rounds of 10 captures; --cull-siblings 0 on the long-list scenes;
# per-level tables.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
ev() { grep -oE 'check [0-9.]+|count [0-9.]+|cull [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|^  digest [0-9a-f]+' | head -6 | tr '\n' ' '; }
B=.device/bnew/sdfbrick
$B scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
S=scenes/stability
for round in 1 2; do
  for sc in "scenes/drops.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" "$S/edits_65536.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "$S/ground_trees.json --brick-size 0.015625" "$S/engraved_slab.json --brick-size 0.015625" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001" "$S/engraved_slab.json --tolerance 0.002"; do
    for v in bhead bnew; do
      echo "$round $sc $v: $(timeout 100 .device/$v/sdfbrick -d gpu build $sc $X 2>&1 | ev)"
    done
  done
done
for sc in "/tmp/sculpt_dense.json" "$S/edits_65536.json" "scenes/sculpt.json"; do
  for v in bhead bnew; do
    echo "$sc $v siblings 0: $(timeout 100 .device/$v/sdfbrick -d gpu build $sc --brick-size 0.0625 --cull-siblings 0 $X 2>&1 | ev)"
  done
done
for sc in /tmp/sculpt_dense.json $S/edits_65536.json scenes/sculpt.json; do
  for v in bhead bnew; do
    echo "== $v $sc"
    timeout 100 .device/$v/sdfbrick -d gpu build $sc --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E '^ +[0-9] |brick_count |cull_mark'
  done
done
echo "pocl drops bnew: $(timeout 100 $B -d cpu build scenes/drops.json --brick-size 0.0625 2>&1 | ev)"
echo "pocl sculpt bnew: $(timeout 100 $B -d cpu build scenes/sculpt.json --brick-size 0.0625 2>&1 | ev)"
