#!/usr/bin/env bash
# After e5's two findings (a lane's setup before the first pass, the first lane on the calling thread,
# no subtree pick for a lane alone): whole against split on one GPU and on NVIDIA + PoCL, alternating.
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick; S=$PWD/.device/scenes
O=$OUT/e6; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=/tmp/tuning.json SDFBRICK_RATES=off
D="$S/drops.json --brick-size 0.0625"
$B -d 0 render $D --width 3840 --height 2160 --mode shaded --out /tmp/w.ppm >/dev/null 2>&1
$B --device 0,1 --devices split render $D --width 3840 --height 2160 --mode shaded --out /tmp/w.ppm >/dev/null 2>&1
R="--warmup 1 --repeat 10"
for round in 1 2 3; do
  $B -d 0 build $D $R --json $O/build-$round.json > $O/build-$round.txt 2>&1
  $B -d 0 --devices split build $D $R --json $O/split1-build-$round.json > $O/split1-build-$round.txt 2>&1
  $B --device 0,1 --devices split build $D $R --json $O/split2-build-$round.json > $O/split2-build-$round.txt 2>&1
  $B -d 0 render $D --width 1920 --height 1080 $R --out /tmp/x.ppm --json $O/render-1080-$round.json > $O/render-1080-$round.txt 2>&1
  $B -d 0 --devices split render $D --width 1920 --height 1080 $R --out /tmp/s.ppm --json $O/split1-render-1080-$round.json > $O/split1-render-1080-$round.txt 2>&1
  $B -d 0 render $D --width 3840 --height 2160 $R --out /tmp/x4.ppm --json $O/render-4k-$round.json > $O/render-4k-$round.txt 2>&1
  $B -d 0 --devices split render $D --width 3840 --height 2160 $R --out /tmp/s4.ppm --json $O/split1-render-4k-$round.json > $O/split1-render-4k-$round.txt 2>&1
  $B --device 0,1 --devices split render $D --width 3840 --height 2160 $R --out /tmp/s24.ppm --json $O/split2-render-4k-$round.json > $O/split2-render-4k-$round.txt 2>&1
done
cmp /tmp/s.ppm /tmp/x.ppm; echo "split1 1080 image same: $((1-$?))" > $O/cmp.txt
cmp /tmp/s4.ppm /tmp/x4.ppm; echo "split1 4K image same: $((1-$?))" >> $O/cmp.txt
cmp /tmp/s24.ppm /tmp/x4.ppm; echo "split2 4K image same: $((1-$?))" >> $O/cmp.txt
for i in 1 2; do $B -d 0 build $D --json $O/build-once-$i.json > $O/build-once-$i.txt 2>&1; done
$B -d 0 build $S/stability/edits_65536.json --brick-size 0.0625 --warmup 1 --repeat 5 --json $O/build-e64k.json > $O/build-e64k.txt 2>&1
$B -d 1 build $D --json $O/pocl-build.json > $O/pocl-build.txt 2>&1
cd $OUT && tar czf e6.tgz e6 && rm -rf e6
