#!/bin/bash
# Adaptive hard cases on the H200 (NVIDIA) and PoCL: uniform against adaptive, build and render --compare.
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/a1; mkdir -p $R
$B devices > $R/devices.txt 2>&1
S=scenes/stability
for n in ground_trees engraved_slab grooved_board steep_blends; do
  for cfg in "u0625:--brick-size 0.0625" "u015625:--brick-size 0.015625" "a002:--tolerance 0.002"; do
    tag=${cfg%%:*}; args=${cfg#*:}
    timeout 120 $B -d gpu build $S/$n.json $args --repeat 10 --warmup 1 --json $R/build-$n-$tag.json > $R/build-$n-$tag.txt 2>&1
    timeout 120 $B -d gpu render $S/$n.json $args --width 1920 --height 1080 --method hybrid --compare --out $R/$n-$tag.png --json $R/render-$n-$tag.json > $R/render-$n-$tag.txt 2>&1
  done
done
for n in board drops; do
  for cfg in "u03125:--brick-size 0.03125" "a001:--tolerance 0.001 --brick-size 0.03125"; do
    tag=${cfg%%:*}; args=${cfg#*:}
    timeout 120 $B -d gpu build scenes/$n.json $args --repeat 10 --warmup 1 --json $R/build-$n-$tag.json > $R/build-$n-$tag.txt 2>&1
  done
done
# PoCL (the machine's CPU cores): the hard cases at tolerance 0.008 (finest 0.0625) against uniform 0.0625
for n in ground_trees engraved_slab grooved_board steep_blends; do
  for cfg in "u0625:--brick-size 0.0625" "a008:--tolerance 0.008"; do
    tag=${cfg%%:*}; args=${cfg#*:}
    timeout 100 $B -d cpu build $S/$n.json $args --repeat 3 --warmup 1 --json $R/cpu-build-$n-$tag.json > $R/cpu-build-$n-$tag.txt 2>&1
  done
done
# the new cases' atlas on NVIDIA and PoCL, uniform and adaptive
timeout 200 $B -d all stability $S/ground_trees.json $S/engraved_slab.json $S/grooved_board.json $S/steep_blends.json --normals continuous --formats int8 --json $R/atlas-new.json > $R/atlas-new.txt 2>&1
rm -f $R/*.png
cd $OUT && tar czf a1.tgz a1 && rm -rf a1
