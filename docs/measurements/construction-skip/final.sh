#!/usr/bin/env bash
# The final binary with default settings (no apron sharing, far sphere and capsule edits skipped)
# against main before the change (sdfbrick-main, c8058bd, default settings); drops in two
# alternating rounds, the other scenes in one; main without sharing on rubble.
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick; M=$PWD/.device/bin/sdfbrick-main
O=$OUT/final; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=$O/tuning.json
R="--brick-size 0.0625 --warmup 1 --repeat 10"
for round in 1 2; do
  $M -d 0 build scenes/drops.json $R > $O/drops-before-$round.txt 2>&1
  $B -d 0 build scenes/drops.json $R --json $O/drops-after-$round.json > $O/drops-after-$round.txt 2>&1
done
for sc in sculpt rubble rain cubes; do
  $M -d 0 build scenes/$sc.json $R > $O/$sc-before-1.txt 2>&1
  $B -d 0 build scenes/$sc.json $R --json $O/$sc-after-1.json > $O/$sc-after-1.txt 2>&1
done
$M -d 0 build scenes/rubble.json $R --apron-share-edits 0 > $O/rubble-before-k0-1.txt 2>&1
$B -d 0 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 3 --kernel-stats > $O/drops-stats.txt 2>&1
cd $O && for f in *.txt; do printf "%-24s %s | %s | %s\n" $f "$(grep -o 'total over.*median [0-9.]* ms' $f | grep -o '[0-9.]* ms')" "$(grep -o 'count [0-9.]*, .*evaluate [0-9.]*' $f)" "$(grep -o 'digest [0-9a-f]*' $f)"; done
grep -h "brick_evaluate " $O/drops-stats.txt; grep -h "^    [a-z]* .*GFLOP" $O/drops-after-1.txt
cd $OUT && tar czf final.tgz final && rm -rf final
