#!/bin/bash
# The sibling cull in SIMD lanes on CPUs: the count-lanes binary (A) against the new one (B), PoCL
# here, alternating, two rounds, medians of 3.
A=.device/bcount/sdfbrick; B=build/device/host/sdfbrick
X="-d cpu build --warmup 1 --repeat 3"
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|digest [0-9a-f]+' | tr '\n' ' '; }
S=scenes/stability
for round in 1 2; do
  for sc in "$S/engraved_slab.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "scenes/drops.json --brick-size 0.125" "scenes/sculpt.json --brick-size 0.0625" "scenes/cubes.json" "scenes/board.json --brick-size 0.0625" "scenes/board.json --brick-size 0.0625 --tolerance 0.004" "$S/grooved_board.json --brick-size 0.0625 --tolerance 0.008" "scenes/board.json --brick-size 0.0625 --branching 2 --tolerance 0.004"; do
    for v in A B; do
      bin=$A; [ $v = B ] && bin=$B
      echo "$round $v $sc: $($bin $X $sc 2>&1 | ev)"
    done
  done
done
