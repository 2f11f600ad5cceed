#!/bin/bash
# The final binary of this round (the compacted 4-wide BVH, analytic corners as a float8, the H200's
# new trace group 8 x 16): drops' build, 4K traces and 1080p shaded frames, 1080p frames of other
# scenes (NVIDIA, 10 captures); NVIDIA against PoCL images; and PoCL (16 cores) traces against the
# binary BVH's binary (sdfbrick-base), alternating, two rounds.
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/d16; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10 --kernel-stats"
D="scenes/drops.json --brick-size 0.0625"
$B -d gpu build $D $X --json $R/build-drops.json > $R/build-drops.txt 2>&1
for m in sphere hybrid analytic; do
  $B -d gpu render $D --width 3840 --height 2160 --method $m $X --out /tmp/r4k.ppm --json $R/r4k-$m.json > $R/r4k-$m.txt 2>&1
  $B -d gpu render $D --width 1920 --height 1080 --mode shaded --method $m $X --out /tmp/sh.ppm --json $R/shade-$m.json > $R/shade-$m.txt 2>&1
done
for s in rain rubble board gears stability/ground_trees stability/grooved_board stability/instances_10000; do
  $B -d gpu render scenes/$s.json --width 1920 --height 1080 $X --out /tmp/o.ppm --json $R/r1080-$(basename $s).json > $R/r1080-$(basename $s).txt 2>&1
done
for m in sphere hybrid analytic; do
  for mode in shaded normals bricks; do
    $B -d cpu render $D --width 480 --height 270 --mode $mode --method $m --out /tmp/c-$mode-$m.ppm > /dev/null 2>&1
    $B -d gpu render $D --width 480 --height 270 --mode $mode --method $m --out /tmp/g-$mode-$m.ppm > /dev/null 2>&1
    cmp -s /tmp/c-$mode-$m.ppm /tmp/g-$mode-$m.ppm; echo "$mode 480x270 $m NVIDIA = PoCL: $((1-$?))" >> $R/cmp.txt
  done
done
for round in 1 2; do
  for b in sdfbrick-base sdfbrick; do
    for m in sphere analytic; do
      .device/bin/$b -d cpu render scenes/drops.json --brick-size 0.125 --width 1280 --height 720 --method $m --warmup 1 --repeat 3 --out /tmp/p.ppm > $R/pocl-$m-$b-$round.txt 2>&1
    done
  done
done
cd $OUT && tar czf d16.tgz d16 && rm -rf d16
