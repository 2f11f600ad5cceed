#!/bin/bash
# The final binary of the session on NVIDIA: adaptive builds of d8 at E = 0.002 (drops and board:
# 0.03125, E = 0.001) beside uniform builds at the finest size, alternating, two rounds.
source .device/env.sh
R=$OUT/d12; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
S=scenes/stability
B=.device/bin/sdfbrick
X="--warmup 1 --repeat 10 --kernel-stats"
for round in 1 2; do
  for n in ground_trees engraved_slab grooved_board steep_blends drops board; do
    f=$S/$n.json; a="--tolerance 0.002"; u=0.015625
    case $n in drops|board) f=scenes/$n.json; a="--brick-size 0.03125 --tolerance 0.001"; u=0.03125;; esac
    timeout 100 $B -d gpu build $f $a $X --json $R/gpu-$n-$round.json > $R/gpu-$n-$round.txt 2>&1
    timeout 100 $B -d gpu build $f --brick-size $u $X --json $R/gpu-$n-uniform-$round.json > $R/gpu-$n-uniform-$round.txt 2>&1
  done
done
cd $OUT && tar czf d12.tgz d12 && rm -rf d12
