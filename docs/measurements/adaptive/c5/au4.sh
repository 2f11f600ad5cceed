#!/bin/bash
# Uniform against adaptive at 0.0625 after the cell centre's zero fourth lane (PoCL here, 2 cores):
# three rounds alternating, medians of 5; prints leaves, stage medians and digests.
B=build/release/host/sdfbrick
S=scenes/stability
for r in 1 2 3; do
  for a in "$S/engraved_slab.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" \
           "scenes/board.json --brick-size 0.0625" "scenes/board.json --brick-size 0.0625 --tolerance 0.004" \
           "$S/grooved_board.json --brick-size 0.0625" "$S/grooved_board.json --brick-size 0.0625 --tolerance 0.008"; do
    echo "$r $a: $($B build $a --warmup 1 --repeat 5 2>&1 | grep -oE '[0-9]+ leaf bricks|stages.*|^  digest [0-9a-f]+' | tr '\n' ' ')"
  done
done
