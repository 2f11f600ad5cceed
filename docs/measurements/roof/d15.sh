#!/bin/bash
# After the 4-wide BVH: analytic cells that load their eight corners once, as a float8 (kf8, loaded
# with --kernel-dir) against the embedded kernels, alternating, two rounds of 10 captures; the trace
# work-group shapes of the new traversal (4K sphere and hybrid, 5 captures each); the full `tune`
# search on drops (NVIDIA).
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/d15; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=/tmp/tuning.json
X="--warmup 1 --repeat 10 --kernel-stats"
D="scenes/drops.json --brick-size 0.0625"
for round in 1 2; do
  for v in emb f8; do
    K=""; [ $v = f8 ] && K="--kernel-dir .device/kf8"
    for m in hybrid analytic; do
      $B -d gpu render $D --width 3840 --height 2160 --method $m $X $K --out /tmp/r4k-$m-$v.ppm > $R/r4k-$m-$v-$round.txt 2>&1
      $B -d gpu render $D --width 1920 --height 1080 --mode shaded --method $m $X $K --out /tmp/sh-$m-$v.ppm > $R/shade-$m-$v-$round.txt 2>&1
    done
  done
done
for m in hybrid analytic; do
  cmp -s /tmp/r4k-$m-emb.ppm /tmp/r4k-$m-f8.ppm; echo "4K $m f8 = embedded: $((1-$?))" >> $R/cmp.txt
  cmp -s /tmp/sh-$m-emb.ppm /tmp/sh-$m-f8.ppm; echo "shaded $m f8 = embedded: $((1-$?))" >> $R/cmp.txt
done
for g in 4x16 8x8 16x8 8x16 4x32 32x4 16x16 8x4; do
  gx=${g%x*}; gy=${g#*x}
  for m in sphere hybrid; do
    $B -d gpu render $D --width 3840 --height 2160 --method $m --warmup 1 --repeat 5 --group-x $gx --group-y $gy --out /tmp/g.ppm > $R/group-$g-$m.txt 2>&1
  done
done
timeout 300 $B -d gpu tune $D --width 3840 --height 2160 --repeat 5 --json $R/tune-h200.json > $R/tune-h200.txt 2>&1
cp /tmp/tuning.json $R/tuning-db.json 2>/dev/null
cd $OUT && tar czf d15.tgz d15 && rm -rf d15
