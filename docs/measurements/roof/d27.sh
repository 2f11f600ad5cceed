#!/bin/bash
# PoCL on the 16 cores, after the check's deep flags in the points' numbering and its vector
# maximum (this commit's kernels, .device/knew, --kernel-dir, with d25's binary): adaptive builds
# of the hard cases, drops and board (0.0625, E = 0.008; drops and board E = 0.004) beside uniform
# builds at 0.0625, alternating, two rounds, 5 captures each; digests against NVIDIA's for the
# adaptive builds at the same settings.
source .device/env.sh
B=$PWD/.device/bin/sdfbrick
K="--kernel-dir $PWD/.device/knew"
R=$OUT/d27; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
S=scenes/stability
for round in 1 2; do
  for n in ground_trees engraved_slab grooved_board steep_blends drops board; do
    f=$S/$n.json; p="--brick-size 0.0625 --tolerance 0.008"
    case $n in drops|board) f=scenes/$n.json; p="--brick-size 0.0625 --tolerance 0.004";; esac
    timeout 100 $B $K -d cpu build $f $p --warmup 1 --repeat 5 > $R/cpu-adaptive-$n-$round.txt 2>&1
    timeout 100 $B $K -d cpu build $f --brick-size 0.0625 --warmup 1 --repeat 5 > $R/cpu-uniform-$n-$round.txt 2>&1
    [ $round = 1 ] && timeout 100 $B $K -d gpu build $f $p > $R/gpu-adaptive-$n.txt 2>&1
  done
done
for f in $R/*.txt; do echo "$(basename $f): $(grep -oE 'total [0-9.]+ ms' $f | head -1) $(grep -oE 'check [0-9.]+' $f | head -1) $(grep -oE '[0-9]+ leaf bricks' $f | head -1) $(grep -oE '^  digest [0-9a-f]+' $f)"; done
cd $OUT && tar czf d27.tgz d27 && rm -rf d27
