#!/bin/bash
# PoCL (16 cores) and NVIDIA builds after the check's SIMD lanes: adaptive against uniform.
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/a5; mkdir -p $R
S=scenes/stability
for n in ground_trees engraved_slab grooved_board steep_blends; do
  for cfg in "u0625:--brick-size 0.0625" "a008:--tolerance 0.008"; do
    tag=${cfg%%:*}; args=${cfg#*:}
    timeout 100 $B -d cpu build $S/$n.json $args --repeat 5 --warmup 1 --json $R/cpu-build-$n-$tag.json > $R/cpu-build-$n-$tag.txt 2>&1
  done
done
for cfg in "u0625:--brick-size 0.0625" "a002:--brick-size 0.0625 --tolerance 0.002"; do
  tag=${cfg%%:*}; args=${cfg#*:}
  timeout 100 $B -d cpu build scenes/drops.json $args --repeat 5 --warmup 1 --json $R/cpu-build-drops-$tag.json > $R/cpu-build-drops-$tag.txt 2>&1
done
for n in ground_trees engraved_slab grooved_board steep_blends; do
  timeout 100 $B -d gpu build $S/$n.json --tolerance 0.002 --repeat 10 --warmup 1 --json $R/build-$n-a002.json > $R/build-$n-a002.txt 2>&1
done
timeout 200 $B -d all stability $S/ground_trees.json $S/engraved_slab.json $S/grooved_board.json $S/steep_blends.json --normals continuous --formats int8 --json $R/atlas-new.json > $R/atlas-new.txt 2>&1
cd $OUT && tar czf a5.tgz a5 && rm -rf a5
