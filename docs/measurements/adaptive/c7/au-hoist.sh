#!/bin/bash
# PoCL here (2 cores): adaptive against uniform builds at 0.0625 with main at f667892 (release build),
# three rounds in turn, medians of 3 captures; device and wall ms, leaves.
B=${SDFBRICK:-build/release/host/sdfbrick}
S=scenes/stability
ev() { grep -oE '^  geometry [^:]+: [0-9]+ leaf bricks|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+' | head -5 | tr '\n' ' '; }
for r in 1 2 3; do
  for c in "$S/engraved_slab.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" \
           "scenes/board.json --brick-size 0.0625" "scenes/board.json --brick-size 0.0625 --tolerance 0.004"; do
    echo "$r $c: $($B -d cpu build $c --warmup 1 --repeat 3 2>&1 | ev)"
  done
done
