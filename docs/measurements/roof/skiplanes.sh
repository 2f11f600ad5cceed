#!/bin/bash
# The work-item skip test of sphere and capsule edits in CPU lanes: --no-skip-far against the
# default, the same binary, PoCL here, alternating, two rounds, medians of 3.
B=build/device/host/sdfbrick
ev() { grep -oE 'evaluate [0-9.]+|check [0-9.]+|total [0-9.]+ ms|digest [0-9a-f]+' | tr '\n' ' '; }
for round in 1 2; do
  for sc in "scenes/sculpt.json --brick-size 0.125" "scenes/sculpt.json --brick-size 0.0625" "scenes/drops.json --brick-size 0.125" "scenes/drops.json --brick-size 0.0625 --tolerance 0.004" "scenes/stability/ground_trees.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.125"; do
    for v in "--no-skip-far" ""; do
      echo "$round $sc [$v]: $($B -d cpu build $sc --warmup 1 --repeat 3 $v 2>&1 | ev)"
    done
  done
done
