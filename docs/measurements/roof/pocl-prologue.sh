#!/bin/bash
# PoCL here (2 cores): 518e082's release binary (old) against 3777b12's (new: the evaluation's
# prologue, the kept counts in the scan), alternating, three rounds of 3 captures after a warm-up.
OLD=${OLD:-/tmp/oldmain/build/release/host/sdfbrick}
NEW=${NEW:-build/release/host/sdfbrick}
S=scenes/stability
ev() { grep -oE 'evaluate [0-9.]+|count [0-9.]+|cull [0-9.]+|check [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+' | tr '\n' ' '; }
for r in 1 2 3; do
  for c in "scenes/drops.json --brick-size 0.125" "scenes/rubble.json --brick-size 0.125" "scenes/board.json --brick-size 0.0625" \
           "$S/engraved_slab.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008"; do
    echo "$r old $c: $($OLD -d cpu build $c --warmup 1 --repeat 3 2>&1 | ev)"
    echo "$r new $c: $($NEW -d cpu build $c --warmup 1 --repeat 3 2>&1 | ev)"
  done
done
