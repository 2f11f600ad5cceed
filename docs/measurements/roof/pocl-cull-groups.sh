#!/bin/bash
# PoCL 3.1 here (2 cores): 54fbe71's device-preset binary (bo, /tmp/device_bin) against bf617eb's plus
# the per-level kernel rows of d57 (bc), alternating, 3 rounds of 3 captures.
cd /work/main
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+' | head -10 | tr '\n' ' '; }
for r in 1 2 3; do
  for sc in "scenes/drops.json --brick-size 0.125" "scenes/sculpt.json --brick-size 0.125" "scenes/rubble.json --brick-size 0.125" "scenes/stability/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "scenes/stability/edits_65536.json --brick-size 0.25"; do
    echo "$r bo $sc: $(SDFBRICK_CACHE_DIR=/tmp/sdfc_old LD_LIBRARY_PATH=/tmp/device_bin/lib /tmp/device_bin/bin/sdfbrick -d cpu build $sc --warmup 1 --repeat 3 2>&1 | ev)"
    echo "$r bc $sc: $(SDFBRICK_CACHE_DIR=/tmp/sdfc_new .device/bc/sdfbrick -d cpu build $sc --warmup 1 --repeat 3 2>&1 | ev)"
  done
done
