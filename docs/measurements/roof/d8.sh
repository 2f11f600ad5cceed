#!/bin/bash
# The final state of this round (sdfbrick: the check's faster classes, kept check samples, the
# parents' re-cull on CPUs only, leaf keys for the order stage, count splits on CPUs) against the
# binary before it (sdfbrick-base, ed6568b), alternating, two rounds, adaptive and uniform builds:
# NVIDIA at E = 0.002 against uniform 0.015625 (drops and board: E = 0.001 against uniform 0.03125),
# PoCL on 16 cores at E = 0.008 against uniform 0.0625 (drops and board: E = 0.004).
source .device/env.sh
R=$OUT/d8; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
S=scenes/stability
X="--warmup 1 --repeat 10 --kernel-stats"
P="--warmup 1 --repeat 5 --kernel-stats"
for round in 1 2; do
  for v in sdfbrick sdfbrick-base; do
    B=.device/bin/$v
    for n in ground_trees engraved_slab grooved_board steep_blends drops board; do
      f=$S/$n.json; g="--tolerance 0.002"; u=0.015625; c="--tolerance 0.008"
      case $n in drops|board) f=scenes/$n.json; g="--brick-size 0.03125 --tolerance 0.001"; u=0.03125; c="--brick-size 0.0625 --tolerance 0.004";; esac
      timeout 100 $B -d gpu build $f $g $X --json $R/gpu-$n-$v-$round.json > $R/gpu-$n-$v-$round.txt 2>&1
      timeout 100 $B -d gpu build $f --brick-size $u $X --json $R/gpu-$n-uniform-$v-$round.json > $R/gpu-$n-uniform-$v-$round.txt 2>&1
      timeout 100 $B -d cpu build $f $c $P --json $R/cpu-$n-$v-$round.json > $R/cpu-$n-$v-$round.txt 2>&1
      timeout 100 $B -d cpu build $f --brick-size 0.0625 $P --json $R/cpu-$n-uniform-$v-$round.json > $R/cpu-$n-uniform-$v-$round.txt 2>&1
    done
  done
done
cd $OUT && tar czf d8.tgz d8 && rm -rf d8
