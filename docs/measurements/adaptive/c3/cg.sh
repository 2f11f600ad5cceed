#!/bin/bash
# The check's work-group on CPUs (XCG: an override in a build made for this run only): 32 (the
# evaluation's tuned group) against 8 and 16, PoCL here, two rounds, medians of 3.
B=build/device/host/sdfbrick
ev() { grep -E '^  brick_check |stages|digest' | sed -E 's/ +/ /g' | grep -oE 'check [0-9.]+|total [0-9.]+ ms|brick_check check [0-9]+ [0-9.]+|digest [0-9a-f]+' | tr '\n' ' '; }
S=scenes/stability
for round in 1 2; do
  for sc in "$S/ground_trees.json --brick-size 0.0625 --tolerance 0.008" "$S/steep_blends.json --brick-size 0.0625 --tolerance 0.008" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "$S/grooved_board.json --brick-size 0.0625 --tolerance 0.008" "scenes/board.json --brick-size 0.0625 --tolerance 0.004" "scenes/drops.json --brick-size 0.0625 --tolerance 0.004"; do
    for g in 32 8 16; do
      echo "$round $g $sc: $(XCG=$g $B -d cpu build $sc --warmup 1 --repeat 3 --kernel-stats 2>&1 | ev)"
    done
  done
done
