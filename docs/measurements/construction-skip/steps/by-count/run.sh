#!/usr/bin/env bash
# The evaluation folding a constant number of values per work-group (shipped kernels/) against the
# same binary with the kernels before the change (--kernel-dir .device/kold/kernels, c8058bd).
# Two alternating rounds of 10 captures per scene.
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick
O=$OUT/bycount; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=$O/tuning.json
R="--brick-size 0.0625 --warmup 1 --repeat 10"
for round in 1 2; do
  for sc in drops rain cubes sculpt; do
    $B --kernel-dir .device/kold/kernels -d 0 build scenes/$sc.json $R > $O/$sc-before-$round.txt 2>&1
    $B -d 0 build scenes/$sc.json $R --json $O/$sc-after-$round.json > $O/$sc-after-$round.txt 2>&1
  done
done
$B -d 0 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 3 --kernel-stats > $O/drops-stats.txt 2>&1
$B --kernel-dir .device/kold/kernels -d 0 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 3 --kernel-stats > $O/drops-stats-before.txt 2>&1
cd $O && for f in *.txt; do printf "%-24s %s | %s | %s\n" $f "$(grep -o 'total over.*median [0-9.]* ms' $f | grep -o '[0-9.]* ms')" "$(grep -o 'count [0-9.]*, .*evaluate [0-9.]*' $f)" "$(grep -o 'digest [0-9a-f]*' $f)"; done
grep -h "brick_evaluate " $O/drops-stats*.txt
which ptxas nvdisasm cuobjdump nvcc ncu 2>&1 | head; ls /usr/local/cuda*/bin 2>/dev/null | head
cd $OUT && tar czf bycount.tgz bycount && tar czf cache.tgz -C /tmp sdfcache && rm -rf bycount
