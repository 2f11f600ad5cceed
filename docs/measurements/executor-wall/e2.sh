#!/usr/bin/env bash
# Wall time against device time: main before this session (M) and now (B), alternating; split on
# one GPU and on GPU + PoCL; digests and images across devices.
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick; M=$PWD/.device/bin/sdfbrick-base; S=$PWD/.device/scenes
O=$OUT/e2; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=/tmp/tuning.json SDFBRICK_RATES=off
for X in $M $B; do $X -d 0 build $S/drops.json --brick-size 0.0625 >/dev/null 2>&1; $X -d 0 render $S/drops.json --width 3840 --height 2160 --mode shaded --out /tmp/w.ppm >/dev/null 2>&1; $X -d 1 build $S/drops.json --brick-size 0.25 >/dev/null 2>&1; done
t() { local s=$(date +%s%N); "$@" > /dev/null 2>&1; echo $(( ($(date +%s%N)-s)/1000000 )); }
D="$S/drops.json --brick-size 0.0625"
for round in 1 2 3; do for X in M B; do bin=${!X}
  echo "$X $round build r1 $(t $bin -d 0 build $D) r21 $(t $bin -d 0 build $D --repeat 21)" >> $O/proc.txt
  echo "$X $round render1080 r1 $(t $bin -d 0 render $D --width 1920 --height 1080 --out /tmp/x.ppm) r21 $(t $bin -d 0 render $D --width 1920 --height 1080 --out /tmp/x.ppm --repeat 21)" >> $O/proc.txt
  echo "$X $round render4K r1 $(t $bin -d 0 render $D --width 3840 --height 2160 --out /tmp/x.ppm) r21 $(t $bin -d 0 render $D --width 3840 --height 2160 --out /tmp/x.ppm --repeat 21)" >> $O/proc.txt
  echo "$X $round split1-build r1 $(t $bin -d 0 --devices split build $D) r21 $(t $bin -d 0 --devices split build $D --repeat 21)" >> $O/proc.txt
done; done
for X in M B; do bin=${!X}
  $bin -d 0 build $D --warmup 1 --repeat 10 --json $O/$X-build-drops.json > $O/$X-build-drops.txt 2>&1
  $bin -d 0 build $D --json $O/$X-build-drops-once.json > $O/$X-build-drops-once.txt 2>&1
  for sc in sculpt rain rubble; do $bin -d 0 build $S/$sc.json --brick-size 0.0625 --warmup 1 --repeat 5 --json $O/$X-build-$sc.json > $O/$X-build-$sc.txt 2>&1; done
  $bin -d 0 render $D --width 1920 --height 1080 --warmup 1 --repeat 10 --out /tmp/x.ppm --json $O/$X-render-1080.json > $O/$X-render-1080.txt 2>&1
  $bin -d 0 render $D --width 3840 --height 2160 --warmup 1 --repeat 10 --out /tmp/x.ppm --json $O/$X-render-4k.json > $O/$X-render-4k.txt 2>&1
  $bin -d 0 render $D --width 3840 --height 2160 --mode shaded --warmup 1 --repeat 5 --out /tmp/$X-shaded.ppm --json $O/$X-render-4k-shaded.json > $O/$X-render-4k-shaded.txt 2>&1
  $bin -d 0 build $S/stability/edits_65536.json --brick-size 0.0625 --warmup 1 --repeat 3 --json $O/$X-build-e64k.json > $O/$X-build-e64k.txt 2>&1
  $bin -d 0 build $S/drops.json --brick-size 0.015625 --warmup 1 --repeat 3 --json $O/$X-build-drops-fine.json > $O/$X-build-drops-fine.txt 2>&1
  $bin -d 0 --devices split build $D --warmup 1 --repeat 10 --json $O/$X-split1-build.json > $O/$X-split1-build.txt 2>&1
  $bin -d 0 --devices split render $D --width 3840 --height 2160 --warmup 1 --repeat 10 --out /tmp/$X-split1.ppm --json $O/$X-split1-render.json > $O/$X-split1-render.txt 2>&1
  $bin --device 0,1 --devices split build $D --warmup 1 --repeat 10 --json $O/$X-split2-build.json > $O/$X-split2-build.txt 2>&1
  $bin --device 0,1 --devices split render $D --width 3840 --height 2160 --warmup 1 --repeat 5 --out /tmp/$X-split2.ppm --json $O/$X-split2-render.json > $O/$X-split2-render.txt 2>&1
done
cmp /tmp/B-split1.ppm /tmp/x.ppm > $O/cmp.txt 2>&1; echo "split1 vs plain 4K: $?" >> $O/cmp.txt
cmp /tmp/B-split2.ppm /tmp/x.ppm >> $O/cmp.txt 2>&1; echo "split2 vs plain 4K: $?" >> $O/cmp.txt
$B -d 1 build $D --json $O/B-pocl-build-drops.json > $O/B-pocl-build-drops.txt 2>&1
$B -d 0,1 build $S/sculpt.json --brick-size 0.125 > $O/B-all-build-sculpt.txt 2>&1
$B -d 0,1 render $S/drops.json --brick-size 0.125 --width 1280 --height 720 --mode shaded --out /tmp/s.ppm > $O/B-all-render.txt 2>&1
$B -d 0,1 render $S/thin.json --tolerance 0.0005 --min-brick-size 0.015625 --width 640 --height 360 --out /tmp/t.ppm > $O/B-all-render-adaptive.txt 2>&1
cd $OUT && tar czf e2.tgz e2 && rm -rf e2
