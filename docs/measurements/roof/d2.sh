#!/bin/bash
# After the trace change: peaks, the H200 tuning search over drops, and the kernels-at-the-roof
# figures with rooflines (NVIDIA, 10 captures).
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/d2; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=/tmp/tuning.json
$B -d all devices --peaks > $R/devices-peaks.txt 2>&1
X="--warmup 1 --repeat 10 --kernel-stats"
D="scenes/drops.json --brick-size 0.0625"
$B -d gpu build $D $X --json $R/build-drops.json > $R/build-drops.txt 2>&1
for m in sphere hybrid analytic; do
  $B -d gpu render $D --width 3840 --height 2160 --method $m $X --out /tmp/r4k-$m.ppm --json $R/r4k-$m.json > $R/r4k-$m.txt 2>&1
  $B -d gpu render $D --width 1920 --height 1080 --mode shaded --method $m $X --out /tmp/sh-$m.ppm --json $R/shade-$m.json > $R/shade-$m.txt 2>&1
  $B -d cpu render $D --width 480 --height 270 --mode shaded --method $m --out /tmp/shc-$m.ppm > $R/pocl-shade-$m.txt 2>&1
  $B -d gpu render $D --width 480 --height 270 --mode shaded --method $m --out /tmp/shg-$m.ppm > $R/gpu-shade-small-$m.txt 2>&1
  cmp -s /tmp/shc-$m.ppm /tmp/shg-$m.ppm; echo "shaded 480x270 $m NVIDIA = PoCL: $((1-$?))" >> $R/cmp.txt
done
timeout 300 $B -d gpu tune $D --width 3840 --height 2160 --repeat 5 --json $R/tune-h200.json > $R/tune-h200.txt 2>&1
cp /tmp/tuning.json $R/tuning-db.json 2>/dev/null
cd $OUT && tar czf d2.tgz d2 && rm -rf d2
