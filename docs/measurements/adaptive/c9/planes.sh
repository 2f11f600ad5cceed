#!/bin/bash
# PoCL here (2 cores): the check passing plane bricks unchecked. old: 9dcd9b6's binary, new: b8752ec's
# (both the device preset); uniform builds at the finest size beside them. Three rounds in turn,
# medians of 3 captures; device and wall ms, leaves, digests.
OLD=${OLD:-.device/bin/sdfbrick} NEW=${NEW:-.device/bin/sdfbrick-new}
S=scenes/stability
ev() { grep -oE '^  geometry [^:]+: [0-9]+ leaf bricks|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+' | head -6 | tr '\n' ' '; }
for r in 1 2 3; do
  for c in "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "scenes/board.json --brick-size 0.0625 --tolerance 0.004" \
           "$S/engraved_slab.json --tolerance 0.002"; do
    for b in OLD NEW; do echo "$r $b $c: $(${!b} -d cpu build $c --warmup 1 --repeat 3 2>&1 | ev)"; done
  done
  for c in "$S/engraved_slab.json --brick-size 0.0625" "scenes/board.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.015625"; do
    echo "$r uniform $c: $($NEW -d cpu build $c --warmup 1 --repeat 3 2>&1 | ev)"
  done
done
