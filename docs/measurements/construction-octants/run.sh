#!/usr/bin/env bash
# (Kept as run; see README.md.) Octant culling and the saturation skip of the leaf evaluation, on and off, in one binary:
# --no-octant-cull turns octant culling off; --kernel-dir .device/ks0 holds kernels/ with
# SATURATION_SKIP forced to 0. Two alternating rounds of 10 captures per scene and variant.
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick
O=$OUT/variants; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=$O/tuning.json
R="--brick-size 0.0625 --warmup 1 --repeat 10"
for round in 1 2; do
  for sc in drops rain cubes sculpt; do
    $B --kernel-dir .device/ks0 -d 0 build scenes/$sc.json $R --no-octant-cull > $O/$sc-none-$round.txt 2>&1
    $B --kernel-dir .device/ks0 -d 0 build scenes/$sc.json $R > $O/$sc-octant-$round.txt 2>&1
    $B -d 0 build scenes/$sc.json $R --no-octant-cull > $O/$sc-saturation-$round.txt 2>&1
    $B -d 0 build scenes/$sc.json $R --json $O/$sc-both-$round.json > $O/$sc-both-$round.txt 2>&1
  done
done
$B -d 0 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 3 --kernel-stats > $O/drops-stats.txt 2>&1
$B --kernel-dir .device/ks0 -d 0 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 3 --kernel-stats --no-octant-cull > $O/drops-stats-none.txt 2>&1
for round in 1 2; do
  for sc in drops cubes; do
    $B --kernel-dir .device/ks0 -d 1 build scenes/$sc.json --brick-size 0.0625 --warmup 1 --repeat 3 --no-octant-cull > $O/cpu-$sc-none-$round.txt 2>&1
    $B -d 1 build scenes/$sc.json --brick-size 0.0625 --warmup 1 --repeat 3 > $O/cpu-$sc-both-$round.txt 2>&1
  done
done
cd $O && for f in *.txt; do printf "%-28s %s | %s | %s\n" $f "$(grep -o 'total over.*median [0-9.]* ms' $f | grep -o '[0-9.]* ms')" "$(grep -o 'count [0-9.]*, .*evaluate [0-9.]*' $f)" "$(grep -o 'digest [0-9a-f]*' $f)"; done
grep -h "evaluate  " $O/drops-*-1.txt
cd $OUT && tar czf variants.tgz variants && rm -rf variants
