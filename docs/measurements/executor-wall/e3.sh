#!/usr/bin/env bash
# After the split-trace change: split renders on one GPU and on GPU + PoCL against the plain render,
# 1920 x 1080 and 3840 x 2160 (normals and shaded); main before this session (M) beside it.
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick; M=$PWD/.device/bin/sdfbrick-base; S=$PWD/.device/scenes
O=$OUT/e3; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=/tmp/tuning.json SDFBRICK_RATES=off
D="$S/drops.json --brick-size 0.0625"
for X in $M $B; do $X -d 0 render $D --width 3840 --height 2160 --mode shaded --out /tmp/w.ppm >/dev/null 2>&1; $X -d 1 build $S/drops.json --brick-size 0.25 >/dev/null 2>&1; done
for X in B M; do bin=${!X}
  for size in "1920 1080" "3840 2160"; do set -- $size
    for mode in normals shaded; do
      $bin -d 0 render $D --width $1 --height $2 --mode $mode --warmup 1 --repeat 10 --out /tmp/$X-plain-$1-$mode.ppm --json $O/$X-plain-$1-$mode.json > $O/$X-plain-$1-$mode.txt 2>&1
      $bin -d 0 --devices split render $D --width $1 --height $2 --mode $mode --warmup 1 --repeat 10 --out /tmp/$X-split1-$1-$mode.ppm --json $O/$X-split1-$1-$mode.json > $O/$X-split1-$1-$mode.txt 2>&1
      $bin --device 0,1 --devices split render $D --width $1 --height $2 --mode $mode --warmup 1 --repeat 5 --out /tmp/$X-split2-$1-$mode.ppm --json $O/$X-split2-$1-$mode.json > $O/$X-split2-$1-$mode.txt 2>&1
      for k in split1 split2; do cmp /tmp/$X-plain-$1-$mode.ppm /tmp/$X-$k-$1-$mode.ppm >/dev/null 2>&1; echo "$X $k $1 $mode same=$((1-$?))" >> $O/cmp.txt; done
    done
  done
done
$B -d 0 build $D --warmup 1 --repeat 10 --json $O/B-build-drops.json > $O/B-build-drops.txt 2>&1
cd $OUT && tar czf e3.tgz e3 && rm -rf e3
