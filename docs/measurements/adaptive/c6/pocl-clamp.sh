#!/bin/bash
# PoCL 3.1 here (2 cores), release builds: base = b95461e, n32 = d5af3cf (a coarse leaf level folds
# with its band and its list reaches its own apron; re-cull from 32 edits). Adaptive and uniform in
# turn, --warmup 1 --repeat 5; device ms per stage (medians) and the digest.
S=scenes/stability
ev() { grep -oE '(count|cull|check|evaluate) [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|  digest [0-9a-f]+' | tr '\n' ' '; }
# pocl-clamp.txt: three rounds over three hard cases
for r in 1 2 3; do for sc in "$S/engraved_slab.json --tolerance 0.008" "$S/ground_trees.json --tolerance 0.008" "$S/steep_blends.json --tolerance 0.008"; do
  for b in base n32; do echo "$r $b $sc: $(/tmp/sdfbrick-$b -d cpu build $sc --brick-size 0.0625 --warmup 1 --repeat 5 2>&1 | ev)"; done; done; done
# pocl-clamp-2.txt: engraved_slab, four rounds base against n32, then n32 uniform against adaptive
for r in 1 2 3 4; do for b in base n32; do echo "$r $b engraved 0.0625 E0.008: $(/tmp/sdfbrick-$b -d cpu build $S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008 --warmup 1 --repeat 5 2>&1 | ev)"; done; done
for r in 1 2 3; do
  echo "$r n32 uniform 0.0625: $(/tmp/sdfbrick-n32 -d cpu build $S/engraved_slab.json --brick-size 0.0625 --warmup 1 --repeat 5 2>&1 | ev)"
  echo "$r n32 adaptive E0.008: $(/tmp/sdfbrick-n32 -d cpu build $S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008 --warmup 1 --repeat 5 2>&1 | ev)"
done
