#!/bin/bash
# The evaluation's skip records (B: .device/bp, bca817c) against the test reading the staged edit (A:
# .device/bq, 19fd185), PoCL here (2 cores), alternating, three rounds, medians of 3; same digests.
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
ev() { grep -oE 'evaluate [0-9.]+|total [0-9.]+ ms|digest [0-9a-f]+' | tr '\n' ' '; }
S=scenes/stability
for round in 1 2 3; do
  for sc in "scenes/drops.json --brick-size 0.125" "scenes/sculpt.json --brick-size 0.125" "scenes/rain.json --brick-size 0.125" "$S/ground_trees.json --brick-size 0.0625" "$S/steep_blends.json --brick-size 0.0625" "scenes/spheres.json"; do
    for v in bq bp; do
      echo "$round $v $sc: $(.device/$v/sdfbrick -d cpu build $sc --warmup 1 --repeat 3 2>&1 | ev)"
    done
  done
done
