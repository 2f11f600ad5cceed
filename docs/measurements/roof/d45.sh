#!/bin/bash
# d45 (the same warm H200 as d44): engraved_slab adaptive (E = 0.002) with the coarsest leaf level
# automatic, at most 0.0625 and at most 0.25, against uniform 0.015625; bn = 1c907e1.
source .device/env.sh; export SDFBRICK_CACHE_DIR=/tmp/sdfcache; S=scenes/stability
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|[0-9]+ leaf bricks of [0-9.]+|^  digest [0-9a-f]+' | head -9 | tr '\n' ' '; }
for r in 1 2; do
  for m in "" "--max-brick-size 0.0625" "--max-brick-size 0.25"; do
    echo "$r [$m] $(.device/bn/sdfbrick -d gpu build $S/engraved_slab.json --tolerance 0.002 $m --warmup 1 --repeat 10 2>&1 | ev)"
  done
  echo "$r U $(.device/bn/sdfbrick -d gpu build $S/engraved_slab.json --brick-size 0.015625 --warmup 1 --repeat 10 2>&1 | ev)"
done
