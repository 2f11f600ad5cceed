#!/bin/bash
# The final binary of the fifth session of 2026-12-04 (compiled-in tuning, no database file):
# drops' 4K traces of each method and 1080p shaded frame (sphere rays); uniform builds of drops,
# sculpt, sculpt_dense and edits_65536 at 0.0625 on NVIDIA with their PoCL digests (16 cores);
# adaptive builds of the hard cases, drops and board on NVIDIA (E = 0.002; drops and board 0.03125
# with E = 0.001) beside uniform builds at the finest size, two rounds.
source .device/env.sh
B=$PWD/.device/bin/sdfbrick
R=$OUT/d25; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10 --kernel-stats"
D="scenes/drops.json --brick-size 0.0625"
for m in sphere hybrid analytic; do
  $B -d gpu render $D --width 3840 --height 2160 --method $m $X --out /tmp/r.ppm --json $R/r4k-$m.json > $R/r4k-$m.txt 2>&1
done
$B -d gpu render $D --width 1920 --height 1080 --mode shaded $X --out /tmp/s.ppm --json $R/shade.json > $R/shade.txt 2>&1
$B scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
$B scene generate stability/edits_65536 -o /tmp/edits_65536.json > /dev/null 2>&1
for sc in scenes/drops.json scenes/sculpt.json /tmp/sculpt_dense.json /tmp/edits_65536.json; do
  n=$(basename $sc .json)
  timeout 120 $B -d gpu build $sc --brick-size 0.0625 $X --json $R/build-$n.json > $R/build-$n.txt 2>&1
  timeout 200 $B -d cpu build $sc --brick-size 0.0625 > $R/cpu-build-$n.txt 2>&1
done
S=scenes/stability
for round in 1 2; do
  for n in ground_trees engraved_slab grooved_board steep_blends drops board; do
    f=$S/$n.json; a="--tolerance 0.002"; u=0.015625
    case $n in drops|board) f=scenes/$n.json; a="--brick-size 0.03125 --tolerance 0.001"; u=0.03125;; esac
    timeout 100 $B -d gpu build $f $a $X > $R/gpu-adaptive-$n-$round.txt 2>&1
    timeout 100 $B -d gpu build $f --brick-size $u $X > $R/gpu-uniform-$n-$round.txt 2>&1
  done
done
for f in $R/build-*.txt $R/cpu-build-*.txt; do echo "$(basename $f): $(grep -oE 'total [0-9.]+ ms' $f | head -1) $(grep -oE '^  digest [0-9a-f]+' $f)"; done
for f in $R/r4k-*.txt $R/shade.txt; do echo "$(basename $f): $(grep -E '^  (trace|shade) ' $f | head -1)"; done
for f in $R/gpu-*.txt; do echo "$(basename $f): $(grep -oE 'total [0-9.]+ ms' $f | head -1) $(grep -oE '[0-9]+ leaf bricks' $f | head -1) $(grep -oE '^  digest [0-9a-f]+' $f)"; done
cd $OUT && tar czf d25.tgz d25 && rm -rf d25
