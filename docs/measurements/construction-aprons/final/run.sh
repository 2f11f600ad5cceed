#!/usr/bin/env bash
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick; M=$PWD/.device/bin/sdfbrick-main
O=$OUT/final; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=$O/tuning.json
R="--brick-size 0.0625 --warmup 1 --repeat 10"
for round in 1 2; do
  for sc in drops rain cubes sculpt; do
    $M -d 0 build scenes/$sc.json $R > $O/$sc-before-$round.txt 2>&1
    $B -d 0 build scenes/$sc.json $R --json $O/$sc-after-$round.json > $O/$sc-after-$round.txt 2>&1
  done
done
for round in 1 2; do
  for sc in drops rain; do
    $M -d 1 build scenes/$sc.json --brick-size 0.0625 --warmup 1 --repeat 3 > $O/cpu-$sc-before-$round.txt 2>&1
    $B -d 1 build scenes/$sc.json --brick-size 0.0625 --warmup 1 --repeat 3 --json $O/cpu-$sc-after-$round.json > $O/cpu-$sc-after-$round.txt 2>&1
  done
done
cd $O && for f in *.txt; do printf "%-24s %s | %s | %s\n" $f "$(grep -o 'total over.*median [0-9.]* ms' $f | grep -o '[0-9.]* ms')" "$(grep -o 'count [0-9.]*, .*evaluate [0-9.]*' $f)" "$(grep -o 'digest [0-9a-f]*' $f)"; done
cd $OUT && tar czf final.tgz final && rm -rf policy
