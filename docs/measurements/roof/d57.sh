#!/bin/bash
# d57: bc (the kept count per word a work-item, the dependencies in their own pass, with bw's
# sibling-cull work-groups; X_LEVELS=1 splits --kernel-stats per level, an override of a build made
# for that run only) against bw (d56) and bin (54fbe71), alternating, two rounds of 10 captures; then
# the evaluation's register cap 0, 64, 56 with bc; bs: bc with cull_write's and cull_mark's bits per
# work-item from the environment (X_WRITE_SPAN, X_MARK_SPAN; an override for this run only).
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+.*' | head -10 | tr '\n' ' '; }
S=scenes/stability
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
.device/bin/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for r in 1 2; do
  for sc in "/tmp/sculpt_dense.json --brick-size 0.0625" "$S/edits_65536.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625" "scenes/drops.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001" "scenes/drops.json --brick-size 0.0625 --dependencies"; do
    for v in bin bw bc; do
      echo "$r $v $sc: $(timeout 60 .device/$v/sdfbrick -d gpu build $sc $X 2>&1 | ev)"
    done
    echo "$r bs w1 $sc: $(X_WRITE_SPAN=1 timeout 60 .device/bs/sdfbrick -d gpu build $sc $X 2>&1 | ev)"
    echo "$r bs w1 m1 $sc: $(X_WRITE_SPAN=1 X_MARK_SPAN=1 timeout 60 .device/bs/sdfbrick -d gpu build $sc $X 2>&1 | ev)"
  done
done
for r in 1 2; do
  for sc in "/tmp/sculpt_dense.json" "scenes/drops.json" "scenes/rubble.json"; do
    for g in 0 64 56; do
      echo "$r bc registers $g $sc: $(timeout 60 .device/bc/sdfbrick -d gpu build $sc --brick-size 0.0625 $X --eval-max-registers $g 2>&1 | ev)"
    done
  done
done
for sc in /tmp/sculpt_dense.json scenes/drops.json; do
  for v in bc bs; do
    echo "== $v $sc (bs: X_WRITE_SPAN=1)"
    X_WRITE_SPAN=1 X_LEVELS=1 timeout 100 .device/$v/sdfbrick -d gpu build $sc --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E '^ +[0-9] |cull|sibling|count|write|scan'
  done
done
for d in gpu cpu; do echo "bc $d drops 0.125: $(timeout 120 .device/bc/sdfbrick -d $d build scenes/drops.json --brick-size 0.125 2>&1 | ev)"; done
echo "bc cpu drops 0.125 dependencies: $(timeout 120 .device/bc/sdfbrick -d cpu build scenes/drops.json --brick-size 0.125 --dependencies 2>&1 | ev)"
echo "bc gpu drops 0.125 dependencies: $(timeout 120 .device/bc/sdfbrick -d gpu build scenes/drops.json --brick-size 0.125 --dependencies 2>&1 | ev)"
