#!/usr/bin/env bash
# After the one executor (whole, replicate, split as placements): wall per capture of build and render,
# the split on one GPU and on NVIDIA + PoCL, adaptive and --compare under split against whole.
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick; S=$PWD/.device/scenes
O=$OUT/e5; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=/tmp/tuning.json SDFBRICK_RATES=off
D="$S/drops.json --brick-size 0.0625"
$B -d 0 render $D --width 3840 --height 2160 --mode shaded --out /tmp/w.ppm >/dev/null 2>&1
t() { local s=$(date +%s%N); "$@" > /dev/null 2>&1; echo $(( ($(date +%s%N)-s)/1000000 )); }
for round in 1 2 3; do
  echo "B $round build r1 $(t $B -d 0 build $D) r21 $(t $B -d 0 build $D --repeat 21)" >> $O/proc.txt
  echo "B $round render4K r1 $(t $B -d 0 render $D --width 3840 --height 2160 --out /tmp/x.ppm) r21 $(t $B -d 0 render $D --width 3840 --height 2160 --out /tmp/x.ppm --repeat 21)" >> $O/proc.txt
done
for round in 1 2; do
  $B -d 0 build $D --warmup 1 --repeat 10 --json $O/build-drops-$round.json > $O/build-drops-$round.txt 2>&1
  $B -d 0 --devices split build $D --warmup 1 --repeat 10 --json $O/split1-build-$round.json > $O/split1-build-$round.txt 2>&1
  $B --device 0,1 --devices split build $D --warmup 1 --repeat 10 --json $O/split2-build-$round.json > $O/split2-build-$round.txt 2>&1
  $B -d 0 render $D --width 1920 --height 1080 --warmup 1 --repeat 10 --out /tmp/x.ppm --json $O/render-1080-$round.json > $O/render-1080-$round.txt 2>&1
  $B -d 0 --devices split render $D --width 1920 --height 1080 --warmup 1 --repeat 10 --out /tmp/s.ppm --json $O/split1-render-1080-$round.json > $O/split1-render-1080-$round.txt 2>&1
  $B -d 0 render $D --width 3840 --height 2160 --warmup 1 --repeat 10 --out /tmp/x.ppm --json $O/render-4k-$round.json > $O/render-4k-$round.txt 2>&1
  $B -d 0 --devices split render $D --width 3840 --height 2160 --warmup 1 --repeat 10 --out /tmp/s.ppm --json $O/split1-render-4k-$round.json > $O/split1-render-4k-$round.txt 2>&1
  $B --device 0,1 --devices split render $D --width 3840 --height 2160 --warmup 1 --repeat 10 --out /tmp/s2.ppm --json $O/split2-render-4k-$round.json > $O/split2-render-4k-$round.txt 2>&1
done
cmp /tmp/s.ppm /tmp/x.ppm; echo "split1 4K image same: $((1-$?))" > $O/cmp.txt
cmp /tmp/s2.ppm /tmp/x.ppm; echo "split2 4K image same: $((1-$?))" >> $O/cmp.txt
$B -d 0 build $D --json $O/build-drops-once.json > $O/build-drops-once.txt 2>&1
$B -d 0 build $S/stability/edits_65536.json --brick-size 0.0625 --warmup 1 --repeat 3 --json $O/build-e64k.json > $O/build-e64k.txt 2>&1
$B -d 0 build $S/drops.json --brick-size 0.015625 --warmup 1 --repeat 3 --json $O/build-drops-fine.json > $O/build-drops-fine.txt 2>&1
# every placement, every feature: digests and accuracy against whole
$B --device 0,1 build $D --json $O/replicate-build.json > $O/replicate-build.txt 2>&1
A="$S/thin.json --brick-size 0.0078125 --tolerance 0.0005"
$B -d 0 build $A --warmup 1 --repeat 5 --json $O/adaptive-whole.json > $O/adaptive-whole.txt 2>&1
$B -d 0 --devices split build $A --warmup 1 --repeat 5 --json $O/adaptive-split1.json > $O/adaptive-split1.txt 2>&1
$B --device 0,1 --devices split build $A --json $O/adaptive-split2.json > $O/adaptive-split2.txt 2>&1
C="$S/drops.json --brick-size 0.0625 --width 1280 --height 720 --compare"
$B -d 0 render $C --out /tmp/c.ppm --json $O/compare-whole.json > $O/compare-whole.txt 2>&1
$B --device 0,1 --devices split render $C --out /tmp/c2.ppm --json $O/compare-split2.json > $O/compare-split2.txt 2>&1
cmp /tmp/c.ppm /tmp/c2.ppm; echo "compare split2 image same: $((1-$?))" >> $O/cmp.txt
cmp /tmp/c-reference.ppm /tmp/c2-reference.ppm; echo "compare split2 reference same: $((1-$?))" >> $O/cmp.txt
cd $OUT && tar czf e5.tgz e5 && rm -rf e5
