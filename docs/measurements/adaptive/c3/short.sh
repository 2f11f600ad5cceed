#!/bin/bash
# The check's points folding the lists culled again for C (hard edits): the sibling-cull binary (A)
# against the new one (B), PoCL here, alternating, three rounds, medians of 3; uniform for reference.
A=.device/bculls/sdfbrick; B=build/device/host/sdfbrick
X="-d cpu build --warmup 1 --repeat 3"
ev() { grep -oE 'max [0-9.]+, p99 [0-9.]+|count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|digest [0-9a-f]+' | tr '\n' ' '; }
S=scenes/stability
for round in 1 2 3; do
  for sc in "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "$S/engraved_slab.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.03125 --tolerance 0.004" "$S/engraved_slab.json --brick-size 0.03125"; do
    for v in A B; do
      bin=$A; [ $v = B ] && bin=$B
      echo "$round $v $sc: $($bin $X $sc 2>&1 | ev)"
    done
  done
done
