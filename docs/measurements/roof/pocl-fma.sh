#!/bin/bash
# PoCL 3.1 here (2 cores): the kernel variants of d63 (ko, kn, kx, ky; see d63.sh) loaded with
# --kernel-dir into the release binary of db1d747, alternating, 3 rounds of 3 captures, CPU lanes.
B=build/release/host/sdfbrick
S=scenes/stability
ev() { grep -oE 'count [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|^  digest [0-9a-f]+' | head -6 | tr '\n' ' '; }
for r in 1 2 3; do
  for c in "scenes/drops.json --brick-size 0.125" "scenes/sculpt.json --brick-size 0.125" "scenes/rubble.json --brick-size 0.125" \
           "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008"; do
    for k in ko kn kx ky; do echo "$r $k $c: $(timeout 300 $B -d cpu --kernel-dir .device/$k build $c --warmup 1 --repeat 3 2>&1 | ev)"; done
  done
done
