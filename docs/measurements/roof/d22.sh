#!/bin/bash
# Any-hit rays that keep a wide node's slots in slot order (embedded) against the sorted order
# (.device/kbase, --kernel-dir: the kernels of the commit before): drops' 1080p shaded frame, sphere
# and hybrid rays, 10 captures, alternating, two rounds, images compared (cmp.txt). Then adaptive
# builds of the hard cases, drops and board with the check that returns at once for a brick
# brick_thin failed, the own-level rank and (CPUs) the re-cull before the finest count, beside
# uniform builds at the finest size: NVIDIA (E = 0.002; drops and board 0.03125 with E = 0.001),
# two rounds, and PoCL on the 16 cores (E = 0.008 at 0.0625; drops and board E = 0.004).
source .device/env.sh
B=$PWD/.device/bin/sdfbrick
K=$PWD/.device/kbase
R=$OUT/d22; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10 --kernel-stats"
D="scenes/drops.json --brick-size 0.0625"
for round in 1 2; do
  for m in sphere hybrid; do
    $B --kernel-dir $K -d gpu render $D --width 1920 --height 1080 --mode shaded --method $m $X --out /tmp/s-old-$m.ppm \
      --json $R/shade-old-$m-$round.json > $R/shade-old-$m-$round.txt 2>&1
    $B -d gpu render $D --width 1920 --height 1080 --mode shaded --method $m $X --out /tmp/s-new-$m.ppm \
      --json $R/shade-new-$m-$round.json > $R/shade-new-$m-$round.txt 2>&1
    cmp -s /tmp/s-old-$m.ppm /tmp/s-new-$m.ppm; echo "round $round $m: same image $((1-$?))" >> $R/cmp.txt
  done
done
$B -d cpu render $D --width 480 --height 270 --mode shaded --out /tmp/s-cpu.ppm > /dev/null 2>&1
$B -d gpu render $D --width 480 --height 270 --mode shaded --out /tmp/s-gpu.ppm > /dev/null 2>&1
cmp -s /tmp/s-cpu.ppm /tmp/s-gpu.ppm; echo "480x270 shaded sphere, NVIDIA = PoCL: $((1-$?))" >> $R/cmp.txt
S=scenes/stability
for round in 1 2; do
  for n in ground_trees engraved_slab grooved_board steep_blends drops board; do
    f=$S/$n.json; a="--tolerance 0.002"; u=0.015625; p="--brick-size 0.0625 --tolerance 0.008"
    case $n in drops|board) f=scenes/$n.json; a="--brick-size 0.03125 --tolerance 0.001"; u=0.03125
                            p="--brick-size 0.0625 --tolerance 0.004";; esac
    timeout 100 $B -d gpu build $f $a $X > $R/gpu-adaptive-$n-$round.txt 2>&1
    timeout 100 $B -d gpu build $f --brick-size $u $X > $R/gpu-uniform-$n-$round.txt 2>&1
    if [ $round = 1 ]; then
      timeout 100 $B -d cpu build $f $p --warmup 1 --repeat 5 > $R/cpu-adaptive-$n.txt 2>&1
      timeout 100 $B -d cpu build $f --brick-size 0.0625 --warmup 1 --repeat 5 > $R/cpu-uniform-$n.txt 2>&1
    fi
  done
done
cd $OUT && tar czf d22.tgz d22 && rm -rf d22
