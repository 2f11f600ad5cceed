#!/usr/bin/env bash
# Final: count's fold without a branch per edit (sdf_fold_params / sdf_fold_select) on top of the
# second step. main before this session's work (sdfbrick-main, 4d5cd4e), the second step
# (sdfbrick-v2, 8cb1e54) and this one, alternating, three rounds of 10 captures for drops, one for
# the other scenes; per-launch JSON, kernel statistics; PoCL on the 16 cores, two rounds.
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick; M=$PWD/.device/bin/sdfbrick-main; V=$PWD/.device/bin/sdfbrick-v2
O=$OUT/final; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=$O/tuning.json
R="--brick-size 0.0625 --warmup 1 --repeat 10"
for round in 1 2 3; do
  $M -d 0 build scenes/drops.json $R > $O/drops-before-$round.txt 2>&1
  $V -d 0 build scenes/drops.json $R > $O/drops-v2-$round.txt 2>&1
  $B -d 0 build scenes/drops.json $R --json $O/drops-after-$round.json > $O/drops-after-$round.txt 2>&1
done
for sc in sculpt rubble rain cubes; do
  $M -d 0 build scenes/$sc.json $R > $O/$sc-before-1.txt 2>&1
  $V -d 0 build scenes/$sc.json $R > $O/$sc-v2-1.txt 2>&1
  $B -d 0 build scenes/$sc.json $R --json $O/$sc-after-1.json > $O/$sc-after-1.txt 2>&1
done
$B -d 0 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 3 --kernel-stats > $O/drops-stats.txt 2>&1
for round in 1 2; do
  $M -d 1 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 3 > $O/pocl-drops-before-$round.txt 2>&1
  $B -d 1 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 3 --json $O/pocl-drops-after-$round.json > $O/pocl-drops-after-$round.txt 2>&1
done
rm -f $O/drops-after-[23].json $O/pocl-drops-after-2.json
cd $O && for f in *.txt; do printf "%-26s %s | %s | %s\n" $f "$(grep -o 'total over.*median [0-9.]* ms' $f | grep -o '[0-9.]* ms')" "$(grep -o 'count [0-9.]*, .*evaluate [0-9.]*' $f)" "$(grep -o 'digest [0-9a-f]*' $f)"; done
cd $OUT && tar czf final.tgz final && rm -rf final
