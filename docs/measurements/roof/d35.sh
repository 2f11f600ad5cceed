#!/bin/bash
# The cull's work-group per parent only where a level has 2 parents or more per compute unit, the count
# without the marks (bnew), against the binary before both (bold: 9d3ef83's build), alternating, two
# rounds of 10 captures; then per-level tables.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
ev() { grep -oE 'check [0-9.]+|count [0-9.]+|cull [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|^  digest [0-9a-f]+' | head -6 | tr '\n' ' '; }
B=.device/bnew/sdfbrick
$B scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
S=scenes/stability
for round in 1 2; do
  for sc in "scenes/drops.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" "$S/edits_65536.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "$S/ground_trees.json --brick-size 0.015625" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001" "$S/engraved_slab.json --tolerance 0.002" "$S/engraved_slab.json --brick-size 0.015625"; do
    for v in bold bnew; do
      echo "$round $sc $v: $(timeout 100 .device/$v/sdfbrick -d gpu build $sc $X 2>&1 | ev)"
    done
  done
done
for sc in "/tmp/sculpt_dense.json --brick-size 0.0625" "$S/edits_65536.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625" "$S/engraved_slab.json --tolerance 0.002" "$S/engraved_slab.json --brick-size 0.015625"; do
  echo "== bnew $sc"
  timeout 100 $B -d gpu build $sc $X --kernel-stats 2>&1 | grep -vE '^\s*$' | tail -40
done
echo "pocl drops: $(timeout 100 $B -d cpu build scenes/drops.json --brick-size 0.0625 2>&1 | ev)"
