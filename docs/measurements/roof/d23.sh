#!/bin/bash
# Packets of any-hit rays (tr_occluded: up to 4 rays from one origin walk the tree together, each
# node read once; not kept): drops 1080p shaded with every ray in packets (embedded), with only
# the shadow rays in packets (.device/kshadow) and none (.device/kbase, the kernels of the commit
# before), sphere and hybrid rays, two rounds; board and ground_trees shaded; images compared.
# The second part (its output, d23b.txt, came back as text) tried register caps of 0, 96 and 128.
B=$PWD/.device/bin/sdfbrick
R=$OUT/d23; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10 --kernel-stats"
D="scenes/drops.json --brick-size 0.0625"
for round in 1 2; do
  for m in sphere hybrid; do
    for v in kbase kshadow packet; do
      K=""; [ $v != packet ] && K="--kernel-dir $PWD/.device/$v"
      $B $K -d gpu render $D --width 1920 --height 1080 --mode shaded --method $m $X --out /tmp/s-$v-$m.ppm \
        --json $R/shade-$v-$m-$round.json > $R/shade-$v-$m-$round.txt 2>&1
      cmp -s /tmp/s-kbase-$m.ppm /tmp/s-$v-$m.ppm; echo "round $round $m $v: same image as kbase $((1-$?))" >> $R/cmp.txt
    done
  done
done
for sc in scenes/board.json scenes/stability/ground_trees.json; do
  for v in kbase packet; do
    K=""; [ $v != packet ] && K="--kernel-dir $PWD/.device/$v"
    $B $K -d gpu render $sc --brick-size 0.0625 --width 1920 --height 1080 --mode shaded $X --out /tmp/m-$v.ppm > $R/shade-$v-$(basename $sc .json).txt 2>&1
  done
  cmp -s /tmp/m-kbase.ppm /tmp/m-packet.ppm; echo "$sc: same image $((1-$?))" >> $R/cmp.txt
  $B -d cpu render $sc --brick-size 0.0625 --width 480 --height 270 --mode shaded --out /tmp/c.ppm > /dev/null 2>&1
  $B -d gpu render $sc --brick-size 0.0625 --width 480 --height 270 --mode shaded --out /tmp/g.ppm > /dev/null 2>&1
  cmp -s /tmp/c.ppm /tmp/g.ppm; echo "$sc 480x270: NVIDIA = PoCL $((1-$?))" >> $R/cmp.txt
done
cat $R/cmp.txt
for f in $R/shade-*.txt; do echo "$(basename $f) $(grep -E '^  shade ' $f | head -1)"; done
cd $OUT && tar czf d23.tgz d23 && rm -rf d23

# d23b
B=$PWD/.device/bin/sdfbrick
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10 --kernel-stats"
D="scenes/drops.json --brick-size 0.0625"
for c in 0 96 128; do
  for v in kshadow packet; do
    K=""; [ $v != packet ] && K="--kernel-dir $PWD/.device/$v"
    echo "$v cap $c: $($B $K -d gpu render $D --width 1920 --height 1080 --mode shaded --max-registers $c $X --out /tmp/x.ppm 2>&1 | grep -E '^  shade  +shade' | head -1)"
  done
done
