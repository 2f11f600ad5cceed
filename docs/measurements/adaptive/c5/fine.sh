#!/bin/bash
# engraved_slab and board at the finest size the table used (0.015625): uniform against
# adaptive E = 0.002 (finest and coarsest levels automatic), PoCL here, two rounds, medians of 3.
B=build/release/host/sdfbrick
S=scenes/stability
for r in 1 2; do
  for a in "$S/engraved_slab.json --brick-size 0.015625" "$S/engraved_slab.json --tolerance 0.002" \
           "scenes/board.json --brick-size 0.015625" "scenes/board.json --tolerance 0.002"; do
    echo "$r $a: $(timeout 300 $B build $a --warmup 1 --repeat 3 2>&1 | grep -oE '[0-9]+ leaf bricks of [0-9.]+|stages.*|^  digest [0-9a-f]+' | sed -E 's/setup.*//; s/(scan|subdivide|order|aabb) [0-9.]+, //g' | tr '\n' ' ')"
  done
done
