#!/bin/bash
# The 4-wide BVH (sdfbrick) against the binary one (sdfbrick-base): drops' 4K traces and 1080p shaded
# frames, and 1080p frames of other scenes, alternating, two rounds of 10 captures (NVIDIA); images
# of the new binary, NVIDIA against PoCL.
source .device/env.sh
R=$OUT/d13; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10 --kernel-stats"
D="scenes/drops.json --brick-size 0.0625"
for round in 1 2; do
  for b in sdfbrick-base sdfbrick; do
    B=.device/bin/$b
    for m in sphere hybrid analytic; do
      $B -d gpu render $D --width 3840 --height 2160 --method $m $X --out /tmp/r4k-$m.ppm --json $R/r4k-$m-$b-$round.json > $R/r4k-$m-$b-$round.txt 2>&1
    done
    for m in sphere hybrid; do
      $B -d gpu render $D --width 1920 --height 1080 --mode shaded --method $m $X --out /tmp/sh-$m.ppm --json $R/shade-$m-$b-$round.json > $R/shade-$m-$b-$round.txt 2>&1
    done
    for s in rain rubble board gears stability/ground_trees stability/grooved_board stability/instances_10000; do
      n=$(basename $s)
      $B -d gpu render scenes/$s.json --width 1920 --height 1080 $X --out /tmp/o.ppm --json $R/r1080-$n-$b-$round.json > $R/r1080-$n-$b-$round.txt 2>&1
    done
  done
done
B=.device/bin/sdfbrick
for m in sphere hybrid analytic; do
  for mode in shaded normals bricks; do
    $B -d cpu render $D --width 480 --height 270 --mode $mode --method $m --out /tmp/c-$mode-$m.ppm > /dev/null 2>&1
    $B -d gpu render $D --width 480 --height 270 --mode $mode --method $m --out /tmp/g-$mode-$m.ppm > /dev/null 2>&1
    cmp -s /tmp/c-$mode-$m.ppm /tmp/g-$mode-$m.ppm; echo "$mode 480x270 $m NVIDIA = PoCL: $((1-$?))" >> $R/cmp.txt
  done
done
cd $OUT && tar czf d13.tgz d13 && rm -rf d13
