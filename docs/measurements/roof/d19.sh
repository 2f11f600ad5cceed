#!/bin/bash
# The shading kernel's work-group shape and register cap: drops' 1080p shaded frame (sphere rays),
# caps 64, 56, 48 x five shapes, 10 captures each (NVIDIA); every image compared with the first.
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/d19; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10 --kernel-stats"
D="scenes/drops.json --brick-size 0.0625"
for r in 64 56 48; do
  for g in 8x16 8x8 16x8 4x16 32x4; do
    gx=${g%x*}; gy=${g#*x}
    $B -d gpu render $D --width 1920 --height 1080 --mode shaded --max-registers $r --group-x $gx --group-y $gy $X \
      --out /tmp/s-$r-$g.ppm --json $R/shade-$r-$g.json > $R/shade-$r-$g.txt 2>&1
    cmp -s /tmp/s-64-8x16.ppm /tmp/s-$r-$g.ppm; echo "cap $r group $g: same image $((1-$?))" >> $R/cmp.txt
  done
done
cd $OUT && tar czf d19.tgz d19 && rm -rf d19
