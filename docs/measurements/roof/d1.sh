#!/bin/bash
# Kernels at the roof, where they stand (NVIDIA, 10 captures) with trace variants loaded from disk,
# and the adaptive check in parity classes against the one before (kold), NVIDIA and PoCL.
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/d1; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
S=scenes/stability
$B devices --peaks --json $R/devices.json > $R/devices.txt 2>&1
X="--warmup 1 --repeat 10 --kernel-stats"
$B -d gpu build scenes/drops.json --brick-size 0.0625 $X --json $R/build-drops.json > $R/build-drops.txt 2>&1
$B -d gpu build $S/edits_65536.json --brick-size 0.0625 $X --json $R/build-e64k.json > $R/build-e64k.txt 2>&1
for v in base kv1 kv2 kv12; do
  K=""; [ $v != base ] && K="--kernel-dir .device/$v"
  for m in sphere hybrid analytic; do
    $B -d gpu render scenes/drops.json --brick-size 0.0625 --width 3840 --height 2160 --method $m $X $K --out /tmp/r4k-$m-$v.ppm --json $R/r4k-$m-$v.json > $R/r4k-$m-$v.txt 2>&1
  done
  $B -d gpu render scenes/drops.json --brick-size 0.0625 --width 1920 --height 1080 --mode shaded $X $K --out /tmp/sh-$v.ppm --json $R/shade-$v.json > $R/shade-$v.txt 2>&1
  $B -d gpu render scenes/drops.json --brick-size 0.0625 --width 1920 --height 1080 --mode shaded --method hybrid $X $K --out /tmp/shh-$v.ppm --json $R/shadeh-$v.json > $R/shadeh-$v.txt 2>&1
done
for v in kv1 kv2 kv12; do
  for f in r4k-sphere r4k-hybrid r4k-analytic sh shh; do cmp -s /tmp/$f-base.ppm /tmp/$f-$v.ppm; echo "$f $v same=$((1-$?))"; done
done > $R/cmp.txt
# the adaptive check: new (embedded) against kold, alternating
for round in 1 2; do
  for v in new kold; do
    K=""; [ $v != new ] && K="--kernel-dir .device/$v"
    for n in ground_trees engraved_slab grooved_board steep_blends; do
      timeout 100 $B -d gpu build $S/$n.json --tolerance 0.002 $X $K --json $R/gpu-$n-$v-$round.json > $R/gpu-$n-$v-$round.txt 2>&1
      timeout 100 $B -d cpu build $S/$n.json --tolerance 0.008 --warmup 1 --repeat 3 --kernel-stats $K --json $R/cpu-$n-$v-$round.json > $R/cpu-$n-$v-$round.txt 2>&1
    done
    timeout 100 $B -d gpu build scenes/drops.json --brick-size 0.03125 --tolerance 0.001 $X $K --json $R/gpu-drops-$v-$round.json > $R/gpu-drops-$v-$round.txt 2>&1
  done
done
for n in ground_trees engraved_slab grooved_board steep_blends; do
  timeout 100 $B -d cpu build $S/$n.json --brick-size 0.0625 --warmup 1 --repeat 3 --json $R/cpu-$n-u0625.json > $R/cpu-$n-u0625.txt 2>&1
done
cd $OUT && tar czf d1.tgz d1 && rm -rf d1
