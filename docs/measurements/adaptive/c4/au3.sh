#!/bin/bash
# Adaptive against uniform at the finest size, PoCL here (2 cores): the device-preset binary of 611105d
# (A, .device/bin) against 19fd185 (B, .device/bq: the coarsest leaf level from the format's rounding), alternating, four rounds, medians of 5.
X="-d cpu build --warmup 1 --repeat 5"
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|[0-9]+ leaf bricks|digest [0-9a-f]+' | tr '\n' ' '; }
S=scenes/stability
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
for round in 1 2 3 4; do
  for sc in "$S/engraved_slab.json --brick-size 0.0625" "scenes/board.json --brick-size 0.0625"; do
    E=0.008; case "$sc" in *board.json*) E=0.004;; esac
    echo "$round uniform $sc: $(.device/bq/sdfbrick $X $sc 2>&1 | ev)"
    echo "$round A adaptive $sc --tolerance $E: $(.device/bin/sdfbrick $X $sc --tolerance $E 2>&1 | ev)"
    echo "$round B adaptive $sc --tolerance $E: $(.device/bq/sdfbrick $X $sc --tolerance $E 2>&1 | ev)"
  done
done
