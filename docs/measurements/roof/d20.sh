#!/bin/bash
# The final binary: drops' 4K traces and 1080p shaded frame with the compiled-in tuning layer (no
# database file: the H200 entry's 8 x 16 and register cap of 64); adaptive builds of the hard cases,
# drops and board, with the check that skips a value whose points are all outside or deep before
# interpolating (embedded) against the check before it (.device/kin, --kernel-dir), NVIDIA (E =
# 0.002, drops and board 0.03125 with E = 0.001) and PoCL on the 16 cores (E = 0.008 at 0.0625,
# drops and board E = 0.004), alternating, two rounds; uniform builds beside them.
source .device/env.sh
B=$PWD/.device/bin/sdfbrick
K=$PWD/.device/kin
R=$OUT/d20; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10 --kernel-stats"
D="scenes/drops.json --brick-size 0.0625"
for m in sphere hybrid analytic; do
  $B -d gpu render $D --width 3840 --height 2160 --method $m $X --out /tmp/r.ppm --json $R/r4k-$m.json > $R/r4k-$m.txt 2>&1
done
$B -d gpu render $D --width 1920 --height 1080 --mode shaded $X --out /tmp/s.ppm --json $R/shade.json > $R/shade.txt 2>&1
S=scenes/stability
for round in 1 2; do
  for n in ground_trees engraved_slab grooved_board steep_blends drops board; do
    f=$S/$n.json; a="--tolerance 0.002"; u=0.015625; p="--brick-size 0.0625 --tolerance 0.008"
    case $n in drops|board) f=scenes/$n.json; a="--brick-size 0.03125 --tolerance 0.001"; u=0.03125
                            p="--brick-size 0.0625 --tolerance 0.004";; esac
    timeout 100 $B --kernel-dir $K -d gpu build $f $a $X > $R/gpu-old-$n-$round.txt 2>&1
    timeout 100 $B -d gpu build $f $a $X > $R/gpu-new-$n-$round.txt 2>&1
    [ $round = 1 ] && timeout 100 $B -d cpu build $f --brick-size 0.0625 --warmup 1 --repeat 5 > $R/cpu-uniform-$n.txt 2>&1
    timeout 100 $B --kernel-dir $K -d cpu build $f $p --warmup 1 --repeat 5 > $R/cpu-old-$n-$round.txt 2>&1
    timeout 100 $B -d cpu build $f $p --warmup 1 --repeat 5 > $R/cpu-new-$n-$round.txt 2>&1
  done
done
cd $OUT && tar czf d20.tgz d20 && rm -rf d20
