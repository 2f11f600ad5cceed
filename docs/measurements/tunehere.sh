#!/bin/bash
# The evaluation's search on drops 0.25 here (chunk 64, group 8; group 8 and 16 newly in the space)
# against the compiled-in entry (chunk 128, group 32), PoCL here, alternating, two rounds, medians of 3.
B=build/release/host/sdfbrick
ev() { grep -oE 'tuning: [a-z_]+ chunk [0-9]+ group [0-9]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|digest [0-9a-f]+' | tr '\n' ' '; }
S=scenes/stability
for round in 1 2; do
  for sc in "scenes/drops.json --brick-size 0.125" "scenes/sculpt.json --brick-size 0.125" "scenes/rubble.json --brick-size 0.125" "scenes/rain.json --brick-size 0.125" "scenes/cubes.json" "scenes/board.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.0625" "$S/ground_trees.json --brick-size 0.0625 --tolerance 0.008" "$S/steep_blends.json --brick-size 0.0625 --tolerance 0.008" "scenes/spheres.json"; do
    echo "$round builtin $sc: $($B -d cpu build $sc --warmup 1 --repeat 3 2>&1 | ev)"
    echo "$round searched $sc: $($B -d cpu --tuning-db /tmp/tuned-here.json build $sc --warmup 1 --repeat 3 2>&1 | ev)"
  done
done
