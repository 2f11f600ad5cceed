#!/bin/bash
# Bricks that cannot hold a hit left out of the BVH, again: the binary before (bold, 9b96b0b) against
# HEAD's (bnew) on ground_trees' 1080p shaded frame, full and with shadow or occlusion rays alone,
# three rounds; drops' shaded frame and BVH build with the hit test shared by 16 work-items; the
# shaded frames of five other scenes once. Output: d29.txt (came back as text).
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
line() { grep -E '^  build ' | sed -E 's/; device .*//; s/^  build [^,]*, //'; }
G=scenes/stability/ground_trees.json
for round in 1 2 3; do
  for s in "4 8" "4 0" "0 8"; do
    set -- $s
    for v in bold bnew; do
      echo "$round ground_trees shadow $1 ao $2 $v: $(.device/$v/sdfbrick -d gpu render $G --width 1920 --height 1080 --mode shaded --shadow-rays $1 --ao-rays $2 $X --out /tmp/g-$v.ppm 2>&1 | line)"
    done
    cmp -s /tmp/g-bold.ppm /tmp/g-bnew.ppm; echo "same image $((1-$?))"
  done
done
for sc in "scenes/drops.json --brick-size 0.0625" scenes/rubble.json scenes/gears.json scenes/rain.json scenes/stability/grooved_board.json scenes/stability/instances_10000.json; do
  for v in bold bnew; do
    echo "$(basename ${sc%% *}) shade $v: $(.device/$v/sdfbrick -d gpu render $sc --width 1920 --height 1080 --mode shaded $X --out /tmp/o-$v.ppm 2>&1 | line)"
  done
  cmp -s /tmp/o-bold.ppm /tmp/o-bnew.ppm; echo "same image $((1-$?))"
done
echo "kernels (bnew, drops 1080p shaded):"
.device/bnew/sdfbrick -d gpu render scenes/drops.json --brick-size 0.0625 --width 1920 --height 1080 --mode shaded $X --kernel-stats --out /tmp/r.ppm 2>&1 | grep -E "bvh_|shade|trace_primary"
echo "kernels (bnew, ground_trees 1080p shaded):"
.device/bnew/sdfbrick -d gpu render $G --width 1920 --height 1080 --mode shaded $X --kernel-stats --out /tmp/r.ppm 2>&1 | grep -E "bvh_|shade|trace_primary"
echo "evaluation floors (timing only, wrong bits): the shipped kernels, the item test without the fold (k_test), no test and no fold (k_none)"
.device/bnew/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for round in 1 2; do
  for sc in "scenes/drops.json" "/tmp/sculpt_dense.json"; do
    for k in shipped k_test k_none; do
      kd=""; [ $k != shipped ] && kd="--kernel-dir .device/$k"
      echo "$round $(basename $sc) $k: $(.device/bnew/sdfbrick -d gpu $kd build $sc --brick-size 0.0625 $X 2>&1 | grep -oE 'count [0-9.]+|cull [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms' | head -4 | tr '\n' ' ')"
    done
  done
done
