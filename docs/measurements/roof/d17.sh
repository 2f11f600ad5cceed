#!/bin/bash
# Register caps for the trace and shade kernels (--max-registers, NVIDIA's -cl-nv-maxrregcount):
# drops' 4K traces per method and 1080p shaded frames, each cap beside none, two rounds; every image
# compared byte for byte with the uncapped one.
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/d17; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10 --kernel-stats"
D="scenes/drops.json --brick-size 0.0625"
for round in 1 2; do
  for m in sphere hybrid analytic; do
    case $m in sphere) caps="0 64 48";; *) caps="0 96 80 64";; esac
    for r in $caps; do
      $B -d gpu render $D --width 3840 --height 2160 --method $m --max-registers $r $X --out /tmp/r-$m-$r.ppm \
        --json $R/r4k-$m-$r-$round.json > $R/r4k-$m-$r-$round.txt 2>&1
      cmp -s /tmp/r-$m-0.ppm /tmp/r-$m-$r.ppm; echo "4K $m cap $r round $round: same image as uncapped $((1-$?))" >> $R/cmp.txt
    done
  done
  for r in 0 80 64; do
    $B -d gpu render $D --width 1920 --height 1080 --mode shaded --max-registers $r $X --out /tmp/s-$r.ppm \
      --json $R/shade-$r-$round.json > $R/shade-$r-$round.txt 2>&1
    cmp -s /tmp/s-0.ppm /tmp/s-$r.ppm; echo "1080p shaded cap $r round $round: same image as uncapped $((1-$?))" >> $R/cmp.txt
  done
done
$B -d cpu render $D --width 480 --height 270 --method hybrid --max-registers 64 --out /tmp/c.ppm > /dev/null 2>&1
$B -d gpu render $D --width 480 --height 270 --method hybrid --max-registers 64 --out /tmp/g.ppm > /dev/null 2>&1
cmp -s /tmp/c.ppm /tmp/g.ppm; echo "480x270 hybrid cap 64 NVIDIA = PoCL: $((1-$?))" >> $R/cmp.txt
cd $OUT && tar czf d17.tgz d17 && rm -rf d17
# Adaptive builds with the check limited to the points inside each brick's cell (kernels loaded from
# .device/kvar) beside the embedded check and uniform builds at the finest size, alternating, two
# rounds (NVIDIA); the variant's digests on PoCL against NVIDIA.
S=scenes/stability
R=$OUT/d17b; mkdir -p $R
for round in 1 2; do
  for n in ground_trees engraved_slab grooved_board steep_blends drops board; do
    f=$S/$n.json; a="--tolerance 0.002"; u=0.015625
    case $n in drops|board) f=scenes/$n.json; a="--brick-size 0.03125 --tolerance 0.001"; u=0.03125;; esac
    timeout 100 $B -d gpu build $f $a $X --json $R/base-$n-$round.json > $R/base-$n-$round.txt 2>&1
    timeout 100 $B --kernel-dir .device/kvar -d gpu build $f $a $X --json $R/var-$n-$round.json > $R/var-$n-$round.txt 2>&1
    timeout 100 $B -d gpu build $f --brick-size $u $X --json $R/uniform-$n-$round.json > $R/uniform-$n-$round.txt 2>&1
  done
done
for n in grooved_board steep_blends; do
  for d in cpu gpu; do
    timeout 200 $B --kernel-dir .device/kvar -d $d build $S/$n.json --tolerance 0.008 --brick-size 0.0625 > $R/digest-$n-$d.txt 2>&1
  done
done
cd $OUT && tar czf d17b.tgz d17b && rm -rf d17b
