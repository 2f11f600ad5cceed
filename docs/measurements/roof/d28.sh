#!/bin/bash
# Bricks that cannot hold a hit left out of the BVH: the binary before (bold) against the one after
# (bnew) on drops' 4K traces of each method and its 1080p shaded frame, two rounds, images compared;
# then the shaded frame of board and ground_trees, and one PoCL (16 cores) shaded frame of drops.
# Output: d28.txt (came back as text).
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
D="scenes/drops.json --brick-size 0.0625"
line() { grep -E '^  build ' | sed -E 's/; device .*//'; }
for round in 1 2; do
  for m in sphere hybrid analytic; do
    for v in bold bnew; do
      echo "$round 4k $m $v: $(.device/$v/sdfbrick -d gpu render $D --width 3840 --height 2160 --method $m $X --out /tmp/r-$v.ppm 2>&1 | line)"
    done
    cmp -s /tmp/r-bold.ppm /tmp/r-bnew.ppm; echo "same image $((1-$?))"
  done
  for v in bold bnew; do
    echo "$round shade $v: $(.device/$v/sdfbrick -d gpu render $D --width 1920 --height 1080 --mode shaded $X --out /tmp/s-$v.ppm 2>&1 | line)"
  done
  cmp -s /tmp/s-bold.ppm /tmp/s-bnew.ppm; echo "same image $((1-$?))"
done
for sc in scenes/board.json scenes/stability/ground_trees.json; do
  for v in bold bnew; do
    echo "$(basename $sc) shade $v: $(.device/$v/sdfbrick -d gpu render $sc --width 1920 --height 1080 --mode shaded $X --out /tmp/g-$v.ppm 2>&1 | line)"
  done
  cmp -s /tmp/g-bold.ppm /tmp/g-bnew.ppm; echo "same image $((1-$?))"
done
for v in bold bnew; do
  echo "pocl shade $v: $(timeout 100 .device/$v/sdfbrick -d cpu render $D --width 1920 --height 1080 --mode shaded --repeat 3 --out /tmp/p-$v.ppm 2>&1 | line)"
done
cmp -s /tmp/p-bold.ppm /tmp/p-bnew.ppm; echo "same image $((1-$?))"
cmp -s /tmp/p-bnew.ppm /tmp/s-bnew.ppm; echo "pocl = nvidia $((1-$?))"
echo "kernels (bnew, drops 4K sphere):"
.device/bnew/sdfbrick -d gpu render $D --width 3840 --height 2160 $X --kernel-stats --out /tmp/r.ppm 2>&1 | grep -E "bvh_|scan_"
