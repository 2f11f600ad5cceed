#!/bin/bash
# The check's face and edge classes in one phase (embedded) against the commit before, one phase a
# class (.device/kin2, --kernel-dir): adaptive builds of the hard cases, drops and board, NVIDIA (E =
# 0.002; drops and board 0.03125 with E = 0.001) and PoCL on the 16 cores (E = 0.008 at 0.0625; drops
# and board E = 0.004), alternating, two rounds; digests compared across the variants and vendors.
source .device/env.sh
B=$PWD/.device/bin/sdfbrick
K=$PWD/.device/kin2
R=$OUT/d21; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10 --kernel-stats"
S=scenes/stability
for round in 1 2; do
  for n in ground_trees engraved_slab grooved_board steep_blends drops board; do
    f=$S/$n.json; a="--tolerance 0.002"; p="--brick-size 0.0625 --tolerance 0.008"
    case $n in drops|board) f=scenes/$n.json; a="--brick-size 0.03125 --tolerance 0.001"
                            p="--brick-size 0.0625 --tolerance 0.004";; esac
    timeout 100 $B --kernel-dir $K -d gpu build $f $a $X > $R/gpu-old-$n-$round.txt 2>&1
    timeout 100 $B -d gpu build $f $a $X > $R/gpu-new-$n-$round.txt 2>&1
    timeout 100 $B --kernel-dir $K -d cpu build $f $p --warmup 1 --repeat 5 > $R/cpu-old-$n-$round.txt 2>&1
    timeout 100 $B -d cpu build $f $p --warmup 1 --repeat 5 > $R/cpu-new-$n-$round.txt 2>&1
  done
done
cd $OUT && tar czf d21.tgz d21 && rm -rf d21
