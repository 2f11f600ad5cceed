#!/usr/bin/env bash
# After the last kernel commit (one fold-step function, no change meant): fa995e7's binary against
# it, alternating, two rounds of 10 captures of drops at 0.0625, and sculpt once each.
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick; P=$PWD/.device/bin/sdfbrick-fa995e7
O=$OUT/check; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=$O/tuning.json
R="--brick-size 0.0625 --warmup 1 --repeat 10"
for round in 1 2; do
  $P -d 0 build scenes/drops.json $R > $O/drops-fa995e7-$round.txt 2>&1
  $B -d 0 build scenes/drops.json $R > $O/drops-last-$round.txt 2>&1
done
$P -d 0 build scenes/sculpt.json $R > $O/sculpt-fa995e7-1.txt 2>&1
$B -d 0 build scenes/sculpt.json $R > $O/sculpt-last-1.txt 2>&1
cd $O && for f in *.txt; do printf "%-26s %s | %s | %s\n" $f "$(grep -o 'total over.*median [0-9.]* ms' $f | grep -o '[0-9.]* ms')" "$(grep -o 'count [0-9.]*, .*evaluate [0-9.]*' $f)" "$(grep -o 'digest [0-9a-f]*' $f)"; done
cd $OUT && tar czf check.tgz check && rm -rf check
