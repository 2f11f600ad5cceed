#!/bin/bash
# tr_visit with the sorted path as before for nearest-hit rays and the slot-order loop only for
# any-hit rays (knew, the commit) against the sorted path from before any-hit slot order (kold: this
# commit's kernels with the earlier sdf_trace.h), both through --kernel-dir: drops 4K traces and
# 1080p shaded, two rounds, images compared. Output: d26.txt (came back as text).
B=$PWD/.device/bin/sdfbrick
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
D="scenes/drops.json --brick-size 0.0625"
for round in 1 2; do
  for m in sphere hybrid analytic; do
    for v in kold knew; do
      echo "$round $m $v: $($B --kernel-dir $PWD/.device/$v -d gpu render $D --width 3840 --height 2160 --method $m $X --out /tmp/r-$v.ppm 2>&1 | grep -E '^  trace ' | head -1)"
    done
    cmp -s /tmp/r-kold.ppm /tmp/r-knew.ppm; echo "same image $((1-$?))"
  done
  for v in kold knew; do
    echo "$round shade $v: $($B --kernel-dir $PWD/.device/$v -d gpu render $D --width 1920 --height 1080 --mode shaded $X --out /tmp/s-$v.ppm 2>&1 | grep -E '^  shade ' | head -1)"
  done
  cmp -s /tmp/s-kold.ppm /tmp/s-knew.ppm; echo "same image $((1-$?))"
done
