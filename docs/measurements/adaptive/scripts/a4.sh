#!/bin/bash
# Adaptive against uniform on the H200 (NVIDIA) and PoCL after the check's rework: builds (10 captures)
# and 1920x1080 hybrid renders with --compare.
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/a4; mkdir -p $R
S=scenes/stability
for n in ground_trees engraved_slab grooved_board steep_blends; do
  for cfg in "u0625:--brick-size 0.0625" "u015625:--brick-size 0.015625" "a002:--tolerance 0.002"; do
    tag=${cfg%%:*}; args=${cfg#*:}
    timeout 120 $B -d gpu build $S/$n.json $args --repeat 10 --warmup 1 --json $R/build-$n-$tag.json > $R/build-$n-$tag.txt 2>&1
    timeout 120 $B -d gpu render $S/$n.json $args --width 1920 --height 1080 --method hybrid --compare --out $R/$n-$tag.ppm --json $R/render-$n-$tag.json > $R/render-$n-$tag.txt 2>&1
  done
done
for n in board drops spheres; do
  for cfg in "u03125:--brick-size 0.03125" "a001:--tolerance 0.001 --brick-size 0.03125" "a002:--tolerance 0.002 --brick-size 0.03125"; do
    tag=${cfg%%:*}; args=${cfg#*:}
    timeout 120 $B -d gpu build scenes/$n.json $args --repeat 10 --warmup 1 --json $R/build-$n-$tag.json > $R/build-$n-$tag.txt 2>&1
    timeout 120 $B -d gpu render scenes/$n.json $args --width 1920 --height 1080 --method hybrid --compare --out $R/$n-$tag.ppm --json $R/render-$n-$tag.json > $R/render-$n-$tag.txt 2>&1
  done
done
for n in ground_trees engraved_slab grooved_board steep_blends; do
  for cfg in "u0625:--brick-size 0.0625" "a008:--tolerance 0.008"; do
    tag=${cfg%%:*}; args=${cfg#*:}
    timeout 100 $B -d cpu build $S/$n.json $args --repeat 3 --warmup 1 --json $R/cpu-build-$n-$tag.json > $R/cpu-build-$n-$tag.txt 2>&1
  done
done
timeout 100 $B -d all build $S/grooved_board.json --tolerance 0.002 --json $R/both-grooved.json > $R/both-grooved.txt 2>&1
rm -f $R/*.ppm
cd $OUT && tar czf a4.tgz a4 && rm -rf a4
