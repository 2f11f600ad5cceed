#!/usr/bin/env bash
# Fourth and fifth tries (the same script, another binary): count's values first from count_values at the levels with few parents, the fold
# reading them straight from global memory (unrolled by 8, no __local copy), against the second
# step (sdfbrick-v2, 8cb1e54: several work-items per child), alternating, three rounds of 10
# captures for drops, two for sculpt, one for the others; per-launch JSON.
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick; V=$PWD/.device/bin/sdfbrick-v2
O=$OUT/count4; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=$O/tuning.json
R="--brick-size 0.0625 --warmup 1 --repeat 10"
for round in 1 2 3; do
  $V -d 0 build scenes/drops.json $R > $O/drops-v2-$round.txt 2>&1
  $B -d 0 build scenes/drops.json $R --json $O/drops-after-$round.json > $O/drops-after-$round.txt 2>&1
done
for sc in sculpt sculpt rubble rain cubes; do
  $V -d 0 build scenes/$sc.json $R > $O/$sc-v2-$RANDOM.txt 2>&1
  $B -d 0 build scenes/$sc.json $R --json $O/$sc-after.json > $O/$sc-after-$RANDOM.txt 2>&1
done
rm -f $O/drops-after-[23].json
cd $O && for f in *.txt; do printf "%-26s %s | %s | %s\n" $f "$(grep -o 'total over.*median [0-9.]* ms' $f | grep -o '[0-9.]* ms')" "$(grep -o 'count [0-9.]*, .*evaluate [0-9.]*' $f)" "$(grep -o 'digest [0-9a-f]*' $f)"; done
cd $OUT && tar czf count4.tgz count4 && rm -rf count4
