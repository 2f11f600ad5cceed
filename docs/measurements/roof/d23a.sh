#!/bin/bash
# drops 1080p shaded, sphere rays: the shade kernel with shadow and occlusion rays apart (output: d23a.txt)
source .device/env.sh
B=$PWD/.device/bin/sdfbrick
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
D="scenes/drops.json --brick-size 0.0625"
for s in "4 8" "4 0" "0 8" "1 0" "0 1" "0 0"; do
  set -- $s
  echo "shadow $1 ao $2: $($B -d gpu render $D --width 1920 --height 1080 --mode shaded --shadow-rays $1 --ao-rays $2 $X --out /tmp/x.ppm 2>&1 | grep -E '^  shade ' | head -1)"
done
