#!/bin/bash
# d76: where the evaluation in lanes of 2 on the GPU gains (d75: rain, ground_trees, engraved_slab,
# edits_65536, drops) and loses (rubble, sculpt): main's kernels (ks) with an experimental binary
# (sdfbrick-exp: main plus SDF_HOIST_FROM, the mean list from which the evaluation branches once per
# edit, 16 in main, and SDF_FAR_LANES, the work-item's test for other primitives than spheres and
# capsules in lanes too, which the kernels kf compile). Variants: L1 (main), L1 hoisted always
# (SDF_HOIST_FROM=0), L2 (--lanes 2), L2 with that test (kf); two rounds, 10 captures. Then
# adaptive builds in L1, L1h and L2.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
X="--warmup 1 --repeat 10"
S=scenes/stability
B=".device/bin/sdfbrick-exp -d gpu"
ev() { grep -oE 'edits per leaf: mean [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|^  digest [0-9a-f]+' | head -6 | tr '\n' ' '; }
ev2() { grep -oE 'evaluate [0-9.]+|check [0-9.]+|total [0-9.]+ ms|^  digest [0-9a-f]+' | head -4 | tr '\n' ' '; }
$B scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for r in 1 2; do
  for c in "scenes/rain.json --brick-size 0.0625" "$S/ground_trees.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.0625" \
           "$S/edits_65536.json --brick-size 0.0625" "scenes/drops.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" \
           "scenes/sculpt.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" "scenes/board.json --brick-size 0.03125" \
           "scenes/cubes.json --brick-size 0.03125" "scenes/fractal.json --brick-size 0.03125" "scenes/gears.json --brick-size 0.03125" \
           "$S/steep_blends.json --brick-size 0.03125" "$S/grooved_board.json --brick-size 0.03125"; do
    echo "$r L1 $c: $(timeout 60 $B --kernel-dir .device/ks build $c $X 2>&1 | ev)"
    echo "$r L1h $c: $(SDF_HOIST_FROM=0 timeout 60 $B --kernel-dir .device/ks build $c $X 2>&1 | ev)"
    echo "$r L2 $c: $(timeout 60 $B --kernel-dir .device/ks build $c $X --lanes 2 2>&1 | ev)"
    echo "$r L2f $c: $(SDF_FAR_LANES=1 timeout 60 $B --kernel-dir .device/kf build $c $X --lanes 2 2>&1 | ev)"
  done
done
# Adaptive builds: --lanes 2 puts the check's points in lanes of 2 too.
for r in 1 2; do
  for c in "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "$S/engraved_slab.json --tolerance 0.002" \
           "scenes/board.json --brick-size 0.03125 --tolerance 0.001" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001" \
           "$S/steep_blends.json --tolerance 0.002" "$S/ground_trees.json --tolerance 0.002" "$S/grooved_board.json --tolerance 0.002"; do
    echo "$r L1 $c: $(timeout 60 $B --kernel-dir .device/ks build $c $X 2>&1 | ev2)"
    echo "$r L1h $c: $(SDF_HOIST_FROM=0 timeout 60 $B --kernel-dir .device/ks build $c $X 2>&1 | ev2)"
    echo "$r L2 $c: $(timeout 60 $B --kernel-dir .device/ks build $c $X --lanes 2 2>&1 | ev2)"
  done
done
echo "elapsed $SECONDS s"
