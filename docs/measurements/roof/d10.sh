#!/bin/bash
# The check on NVIDIA: the embedded kernels (all cell centres in one class with one lane) against
# kp (the even cell centres first with one lane too, commit 8cb3702), kv2 (the embedded one with
# each class gathering its cells' flags, no per-point table) and kd8 (the check of d8), alternating,
# two rounds; adaptive builds of d8 at E = 0.002 (drops and board: 0.03125, E = 0.001).
source .device/env.sh
R=$OUT/d10; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
S=scenes/stability
B=.device/bin/sdfbrick
X="--warmup 1 --repeat 10 --kernel-stats"
for round in 1 2; do
  for v in new kp kv2 kd8; do
    K=""; [ $v != new ] && K="--kernel-dir .device/$v"
    for n in ground_trees engraved_slab grooved_board steep_blends drops board; do
      f=$S/$n.json; g="--tolerance 0.002"
      case $n in drops|board) f=scenes/$n.json; g="--brick-size 0.03125 --tolerance 0.001";; esac
      timeout 100 $B -d gpu build $f $g $X $K --json $R/gpu-$n-$v-$round.json > $R/gpu-$n-$v-$round.txt 2>&1
    done
  done
done
cd $OUT && tar czf d10.tgz d10 && rm -rf d10
