#!/bin/bash
# Adaptive against uniform at the finest size, this tree's binary, PoCL here, alternating, four
# rounds, medians of 5 captures: engraved_slab (E = 0.008 at 0.0625; E = 0.004 at 0.03125) and board
# (E = 0.004 at 0.0625).
B=build/device/host/sdfbrick
X="-d cpu build --warmup 1 --repeat 5"
ev() { grep -oE 'check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|[0-9]+ leaf bricks|digest [0-9a-f]+' | tr '\n' ' '; }
S=scenes/stability
for round in 1 2 3 4; do
  for sc in "$S/engraved_slab.json --brick-size 0.0625" "scenes/board.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.03125"; do
    E=0.008; case "$sc" in *board.json*|*0.03125*) E=0.004;; esac
    echo "$round uniform $sc: $($B $X $sc 2>&1 | ev)"
    echo "$round adaptive $sc --tolerance $E: $($B $X $sc --tolerance $E 2>&1 | ev)"
  done
done
