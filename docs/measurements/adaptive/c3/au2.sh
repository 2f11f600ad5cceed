#!/bin/bash
# Adaptive against uniform at the finest size on the other hard cases, this tree's binary, PoCL
# here, alternating, three rounds, medians of 3 (E = 0.008 at 0.0625; drops E = 0.004).
B=build/device/host/sdfbrick
X="-d cpu build --warmup 1 --repeat 3"
ev() { grep -oE 'check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|[0-9]+ leaf bricks|digest [0-9a-f]+' | tr '\n' ' '; }
S=scenes/stability
for round in 1 2 3; do
  for sc in "$S/ground_trees.json" "$S/grooved_board.json" "$S/steep_blends.json" "scenes/drops.json"; do
    E=0.008; case "$sc" in *drops*) E=0.004;; esac
    echo "$round uniform $sc: $($B $X $sc --brick-size 0.0625 2>&1 | ev)"
    echo "$round adaptive $sc --tolerance $E: $($B $X $sc --brick-size 0.0625 --tolerance $E 2>&1 | ev)"
  done
done
