#!/bin/bash
# d77: main (9dcd9b6; evaluation branched once per edit on every list): adaptive builds against
# uniform ones at their finest size, one round of 10 captures (device and wall ms, leaves, digests);
# per-kernel stats of engraved_slab at 0.0625, uniform and adaptive (E = 0.008), to attribute the
# adaptive build's extra time; on an H200, drops with the H100's compiled-in entry against the H200's.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
GPU=$(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader); echo "$GPU"
X="--warmup 1 --repeat 10"
S=scenes/stability
B=".device/bin/sdfbrick -d gpu"
ev() { grep -oE '^  geometry [^:]+: [0-9]+ leaf bricks|check [0-9.]+|evaluate [0-9.]+|count [0-9.]+|cull [0-9.]+|order [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+' | head -10 | tr '\n' ' '; }
for c in "$S/ground_trees.json" "$S/engraved_slab.json" "$S/grooved_board.json" "$S/steep_blends.json"; do
  echo "uniform 0.015625 $c: $(timeout 60 $B build $c --brick-size 0.015625 $X 2>&1 | ev)"
  echo "adaptive E 0.002 $c: $(timeout 60 $B build $c --tolerance 0.002 $X 2>&1 | ev)"
done
for c in "scenes/drops.json --brick-size 0.03125" "scenes/board.json --brick-size 0.03125" "$S/engraved_slab.json --brick-size 0.0625"; do
  echo "uniform $c: $(timeout 60 $B build $c $X 2>&1 | ev)"
done
for c in "scenes/drops.json --brick-size 0.03125 --tolerance 0.001" "scenes/board.json --brick-size 0.03125 --tolerance 0.001" \
         "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008"; do
  echo "adaptive $c: $(timeout 60 $B build $c $X 2>&1 | ev)"
done
for t in "" "--tolerance 0.008"; do
  echo "== kernel stats engraved_slab 0.0625 $t"
  timeout 60 $B build $S/engraved_slab.json --brick-size 0.0625 $t $X --kernel-stats 2>&1 | sed -n '/^    level  cell/,$p'
done
if echo "$GPU" | grep -q H200; then
  for r in 1 2; do for e in "" "--chunk 32 --group 64 --eval-max-registers 56" "--chunk 32 --group 64"; do
    echo "$r drops 0.0625 $e: $(timeout 60 $B build scenes/drops.json --brick-size 0.0625 $e $X 2>&1 | ev)"; done; done
fi
echo "elapsed $SECONDS s"
