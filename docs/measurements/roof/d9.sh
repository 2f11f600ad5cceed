#!/bin/bash
# The check kernel's later changes (deep cells in lanes, each point's cell flag once, lane masks
# without memory, the even cell centres first, one atomic per value; embedded) against the check of
# d8 (kd8: brick_check.cl of commit 15020a9, loaded with --kernel-dir), alternating, two rounds, the
# adaptive builds of d8 on NVIDIA and PoCL (16 cores).
source .device/env.sh
R=$OUT/d9; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
S=scenes/stability
B=.device/bin/sdfbrick
X="--warmup 1 --repeat 10 --kernel-stats"
P="--warmup 1 --repeat 5 --kernel-stats"
for round in 1 2; do
  for v in new kd8; do
    K=""; [ $v = kd8 ] && K="--kernel-dir .device/kd8"
    for n in ground_trees engraved_slab grooved_board steep_blends drops board; do
      f=$S/$n.json; g="--tolerance 0.002"; c="--tolerance 0.008"
      case $n in drops|board) f=scenes/$n.json; g="--brick-size 0.03125 --tolerance 0.001"; c="--brick-size 0.0625 --tolerance 0.004";; esac
      timeout 100 $B -d gpu build $f $g $X $K --json $R/gpu-$n-$v-$round.json > $R/gpu-$n-$v-$round.txt 2>&1
      timeout 100 $B -d cpu build $f $c $P $K --json $R/cpu-$n-$v-$round.json > $R/cpu-$n-$v-$round.txt 2>&1
    done
  done
done
cd $OUT && tar czf d9.tgz d9 && rm -rf d9
