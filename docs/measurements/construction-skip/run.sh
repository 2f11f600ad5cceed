#!/usr/bin/env bash
# Skipping far sphere and capsule edits: main before the change (sdfbrick-main, c8058bd) against
# the change, two alternating rounds of 10 captures per scene; with apron sharing off (0) and on
# (16) where lists are long; rain also with the evaluation branching once per edit
# (--kernel-dir .device/khoist/kernels: EVAL_HOIST forced to 1). Then PoCL on the 16 cores.
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick; M=$PWD/.device/bin/sdfbrick-main
O=$OUT/skip; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=$O/tuning.json
R="--brick-size 0.0625 --warmup 1 --repeat 10"
for round in 1 2; do
  for sc in drops sculpt rubble rain cubes; do
    $M -d 0 build scenes/$sc.json $R > $O/$sc-before-$round.txt 2>&1
    $B -d 0 build scenes/$sc.json $R --json $O/$sc-after-$round.json > $O/$sc-after-$round.txt 2>&1
    $B -d 0 build scenes/$sc.json $R --no-skip-far > $O/$sc-noskip-$round.txt 2>&1
    for k in 0 16; do $B -d 0 build scenes/$sc.json $R --apron-share-edits $k > $O/$sc-after-k$k-$round.txt 2>&1; done
  done
  $B --kernel-dir .device/khoist/kernels -d 0 build scenes/rain.json $R > $O/rain-hoist-$round.txt 2>&1
done
$B -d 0 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 3 --kernel-stats > $O/drops-stats.txt 2>&1
for round in 1 2; do
  for sc in drops sculpt; do
    $M -d 1 build scenes/$sc.json --brick-size 0.0625 --warmup 1 --repeat 3 > $O/cpu-$sc-before-$round.txt 2>&1
    $B -d 1 build scenes/$sc.json --brick-size 0.0625 --warmup 1 --repeat 3 --json $O/cpu-$sc-after-$round.json > $O/cpu-$sc-after-$round.txt 2>&1
  done
done
cd $O && for f in *.txt; do printf "%-24s %s | %s | %s\n" $f "$(grep -o 'total over.*median [0-9.]* ms' $f | grep -o '[0-9.]* ms')" "$(grep -o 'count [0-9.]*, .*evaluate [0-9.]*' $f)" "$(grep -o 'digest [0-9a-f]*' $f)"; done
grep -h "edits/brick" -A6 $O/rubble-after-1.txt | head -8
cd $OUT && tar czf skip.tgz skip
