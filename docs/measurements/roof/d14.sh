#!/bin/bash
# The 4-wide BVH, second form (leaf slots searched when popped from the stack; sdfbrick) against the
# first form (slots kept in registers, loaded with --kernel-dir kw1) and the binary BVH
# (sdfbrick-base): drops' 4K traces and 1080p shaded frames, 1080p frames of other scenes,
# alternating, two rounds of 10 captures (NVIDIA).
source .device/env.sh
R=$OUT/d14; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10 --kernel-stats"
D="scenes/drops.json --brick-size 0.0625"
for round in 1 2; do
  for v in base w1 w2; do
    B=".device/bin/sdfbrick"; K=""
    [ $v = base ] && B=".device/bin/sdfbrick-base"
    [ $v = w1 ] && K="--kernel-dir .device/kw1"
    for m in sphere hybrid analytic; do
      $B -d gpu render $D --width 3840 --height 2160 --method $m $X $K --out /tmp/r4k.ppm > $R/r4k-$m-$v-$round.txt 2>&1
      $B -d gpu render $D --width 1920 --height 1080 --mode shaded --method $m $X $K --out /tmp/sh.ppm > $R/shade-$m-$v-$round.txt 2>&1
    done
    for s in rain stability/ground_trees stability/instances_10000; do
      $B -d gpu render scenes/$s.json --width 1920 --height 1080 $X $K --out /tmp/o.ppm > $R/r1080-$(basename $s)-$v-$round.txt 2>&1
    done
  done
done
cd $OUT && tar czf d14.tgz d14 && rm -rf d14
