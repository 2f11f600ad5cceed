#!/bin/bash
# PoCL here (2 cores): uniform against adaptive at the finest size, alternating, three rounds of 5 captures (becda4d).
B=build/release/host/sdfbrick
S=scenes/stability
ev() { grep -oE 'check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|leaf bricks|[0-9]+ leaf' | tr '\n' ' '; }
for r in 1 2 3; do
  for c in "$S/engraved_slab.json --brick-size 0.0625|--tolerance 0.008" "scenes/board.json --brick-size 0.0625|--tolerance 0.004" \
           "$S/engraved_slab.json --brick-size 0.03125|--tolerance 0.004"; do
    base=${c%|*}; tol=${c#*|}
    echo "$r uniform $base: $(timeout 300 $B build $base --warmup 1 --repeat 5 2>&1 | ev)"
    echo "$r adaptive $base $tol: $(timeout 300 $B build $base $tol --warmup 1 --repeat 5 2>&1 | ev)"
  done
done
