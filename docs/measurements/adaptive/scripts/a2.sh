#!/bin/bash
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/a2; mkdir -p $R
S=scenes/stability
for n in ground_trees engraved_slab grooved_board steep_blends; do
  for cfg in "u0625:--brick-size 0.0625" "u015625:--brick-size 0.015625" "a002:--tolerance 0.002"; do
    tag=${cfg%%:*}; args=${cfg#*:}
    timeout 120 $B -d gpu render $S/$n.json $args --width 1920 --height 1080 --method hybrid --compare --out $R/$n-$tag.ppm --json $R/render-$n-$tag.json > $R/render-$n-$tag.txt 2>&1
  done
done
timeout 120 $B -d cpu render $S/grooved_board.json --tolerance 0.008 --width 960 --height 540 --method hybrid --compare --out $R/cpu-gb.ppm --json $R/cpu-render-grooved_board-a008.json > $R/cpu-render-gb.txt 2>&1
rm -f $R/*.ppm
cd $OUT && tar czf a2.tgz a2 && rm -rf a2
