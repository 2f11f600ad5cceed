#!/usr/bin/env bash
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick
O=$OUT/b5; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=$O/tuning.json
for round in 1 2; do
  $B -d 0 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 10 > $O/new-$round.txt 2>&1
  $B --kernel-dir .device/kold -d 0 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 10 > $O/oldkernels-$round.txt 2>&1
  .device/bin/sdfbrick-main -d 0 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 10 > $O/before-$round.txt 2>&1
done
grep -H "digest\|total over\|evaluate   " $O/*.txt
timeout 240 $B -d 0 tune scenes/drops.json --brick-size 0.0625 > $O/tune.txt 2>&1; echo "tune rc=$?"
tail -15 $O/tune.txt
cd $OUT && tar czf b5.tgz b5 && rm -rf b5
