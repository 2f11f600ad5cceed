#!/bin/bash
# The register cap as a tuned parameter: `tune --kernels trace` (full search: 30 shapes x caps 0, 64,
# 96) with the sphere and the hybrid method, each into its own database; drops' 4K traces and 1080p
# shaded frames with the hybrid tune's database (the cap applied by the tuning layer, not a flag).
# Adaptive builds with the check limited to the points inside each brick's cell (embedded) beside the
# check before (.device/kold, --kernel-dir) and uniform builds at the finest size, alternating, two
# rounds; the new check's digests on PoCL against NVIDIA.
source .device/env.sh
B=$PWD/.device/bin/sdfbrick
K=$PWD/.device/kold
R=$OUT/d18; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10 --kernel-stats"
D="scenes/drops.json --brick-size 0.0625"
for m in sphere hybrid; do
  SDFBRICK_TUNING_DB=$R/tuning-$m.json timeout 200 $B -d gpu tune $D --kernels trace --method $m --width 3840 \
    --height 2160 --repeat 5 --budget 90 --json $R/tune-$m.json > $R/tune-$m.txt 2>&1
done
for m in sphere hybrid analytic; do
  SDFBRICK_TUNING_DB=$R/tuning-hybrid.json $B -d gpu render $D --width 3840 --height 2160 --method $m $X \
    --out /tmp/r.ppm --json $R/r4k-$m.json > $R/r4k-$m.txt 2>&1
done
SDFBRICK_TUNING_DB=$R/tuning-hybrid.json $B -d gpu render $D --width 1920 --height 1080 --mode shaded $X \
  --out /tmp/s.ppm --json $R/shade.json > $R/shade.txt 2>&1
S=scenes/stability
for round in 1 2; do
  for n in ground_trees engraved_slab grooved_board steep_blends drops board; do
    f=$S/$n.json; a="--tolerance 0.002"; u=0.015625
    case $n in drops|board) f=scenes/$n.json; a="--brick-size 0.03125 --tolerance 0.001"; u=0.03125;; esac
    timeout 100 $B --kernel-dir $K -d gpu build $f $a $X --json $R/old-$n-$round.json > $R/old-$n-$round.txt 2>&1
    timeout 100 $B -d gpu build $f $a $X --json $R/new-$n-$round.json > $R/new-$n-$round.txt 2>&1
    timeout 100 $B -d gpu build $f --brick-size $u $X --json $R/uniform-$n-$round.json > $R/uniform-$n-$round.txt 2>&1
  done
done
for n in grooved_board steep_blends; do
  for d in cpu gpu; do
    timeout 200 $B -d $d build $S/$n.json --tolerance 0.008 --brick-size 0.0625 > $R/digest-$n-$d.txt 2>&1
  done
done
cd $OUT && tar czf d18.tgz d18 && rm -rf d18
