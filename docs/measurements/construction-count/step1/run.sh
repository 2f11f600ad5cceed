#!/usr/bin/env bash
# Count and cull at the top levels: main before the change (sdfbrick-main, 4d5cd4e) against the
# change (several work-items per child in count where few parents, cull lists written a bit per
# work-item), two alternating rounds of 10 captures for drops, one for the other scenes; the change
# with --count-parts 1 and 2 (the cull change alone, and half the parts); per-launch JSON and
# kernel statistics; then PoCL on the 16 cores.
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick; M=$PWD/.device/bin/sdfbrick-main
O=$OUT/count; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=$O/tuning.json
R="--brick-size 0.0625 --warmup 1 --repeat 10"
for round in 1 2; do
  $M -d 0 build scenes/drops.json $R > $O/drops-before-$round.txt 2>&1
  $B -d 0 build scenes/drops.json $R --json $O/drops-after-$round.json > $O/drops-after-$round.txt 2>&1
  $B -d 0 build scenes/drops.json $R --count-parts 1 > $O/drops-parts1-$round.txt 2>&1
  $B -d 0 build scenes/drops.json $R --count-parts 2 > $O/drops-parts2-$round.txt 2>&1
done
for sc in sculpt rubble rain cubes; do
  $M -d 0 build scenes/$sc.json $R > $O/$sc-before-1.txt 2>&1
  $B -d 0 build scenes/$sc.json $R --json $O/$sc-after-1.json > $O/$sc-after-1.txt 2>&1
done
$B -d 0 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 3 --kernel-stats > $O/drops-stats.txt 2>&1
for round in 1 2; do
  $M -d 1 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 3 > $O/pocl-drops-before-$round.txt 2>&1
  $B -d 1 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 3 --json $O/pocl-drops-after-$round.json > $O/pocl-drops-after-$round.txt 2>&1
done
cd $O && for f in *.txt; do printf "%-26s %s | %s | %s\n" $f "$(grep -o 'total over.*median [0-9.]* ms' $f | grep -o '[0-9.]* ms')" "$(grep -o 'count [0-9.]*, .*evaluate [0-9.]*' $f)" "$(grep -o 'digest [0-9a-f]*' $f)"; done
cd $OUT && tar czf count.tgz count && rm -rf count
