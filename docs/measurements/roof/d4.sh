#!/bin/bash
# Shading with one traversal loop (s1) and cells that read their corners once (h1), against the
# embedded kernels, alternating (NVIDIA, 10 captures).
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/d4; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10 --kernel-stats"
D="scenes/drops.json --brick-size 0.0625"
for round in 1 2; do
for v in base s1 h1; do
  K=""; [ $v != base ] && K="--kernel-dir .device/$v"
  for m in sphere hybrid; do
    $B -d gpu render $D --width 1920 --height 1080 --mode shaded --method $m $X $K --out /tmp/sh-$m-$v.ppm --json $R/shade-$m-$v-$round.json > $R/shade-$m-$v-$round.txt 2>&1
  done
  for m in hybrid analytic; do
    $B -d gpu render $D --width 3840 --height 2160 --method $m $X $K --out /tmp/r4k-$m-$v.ppm --json $R/r4k-$m-$v-$round.json > $R/r4k-$m-$v-$round.txt 2>&1
  done
done
done
for v in s1 h1; do
  for f in sh-sphere sh-hybrid r4k-hybrid r4k-analytic; do cmp -s /tmp/$f-base.ppm /tmp/$f-$v.ppm; echo "$f $v same=$((1-$?))"; done
done > $R/cmp.txt
cd $OUT && tar czf d4.tgz d4 && rm -rf d4
