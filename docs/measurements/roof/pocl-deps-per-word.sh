#!/bin/bash
# PoCL 3.1 here (2 cores): with --dependencies, bf617eb's device-preset binary (bc: the dependencies a
# brick a work-item) against 0797052's (bd: a word a work-item, bits apart), alternating, 3 rounds of 3 captures.
cd /work/main
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+.*' | head -10 | tr '\n' ' '; }
for r in 1 2 3; do
  for sc in "scenes/drops.json --brick-size 0.125" "scenes/sculpt.json --brick-size 0.125" "scenes/rubble.json --brick-size 0.25" "scenes/stability/steep_blends.json --brick-size 0.0625"; do
    for v in bc bd; do
      echo "$r $v $sc: $(SDFBRICK_CACHE_DIR=/tmp/sdfc_$v .device/$v/sdfbrick -d cpu build $sc --dependencies --warmup 1 --repeat 3 2>&1 | ev)"
    done
  done
done
