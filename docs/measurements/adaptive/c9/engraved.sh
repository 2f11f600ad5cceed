#!/bin/bash
# PoCL here (2 cores): engraved_slab at 0.0625, adaptive (E = 0.008) against uniform, with main at
# 8bedf74 (release build), five rounds in turn, medians of 5 captures; device and wall ms.
B=${SDFBRICK:-build/release/host/sdfbrick}
S=scenes/stability
ev() { grep -oE 'check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+' | head -4 | tr '\n' ' '; }
for r in 1 2 3 4 5; do
  for t in "" "--tolerance 0.008"; do
    echo "$r $S/engraved_slab.json --brick-size 0.0625 $t: $($B -d cpu build $S/engraved_slab.json --brick-size 0.0625 $t --warmup 1 --repeat 5 2>&1 | ev)"
  done
done
