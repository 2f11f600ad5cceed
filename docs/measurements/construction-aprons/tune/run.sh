#!/usr/bin/env bash
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick
O=$OUT/tune; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=$O/tuning.json
R="--brick-size 0.0625 --warmup 1 --repeat 10"
timeout 200 $B -d 0 tune scenes/drops.json --brick-size 0.0625 --kernels evaluate > $O/tune.txt 2>&1; echo "tune rc=$?"
tail -12 $O/tune.txt
cat $O/tuning.json 2>/dev/null | head -30
for g in 32 64 128 256; do for c in 16 32; do
  echo -n "group $g chunk $c: "; $B -d 0 build scenes/drops.json $R --group $g --chunk $c 2>&1 | grep -o "total over.*median [0-9.]* ms\|apron [0-9.]*, evaluate [0-9.]*" | tr '\n' ' '; echo
done; done
cd $OUT && tar czf tune.tgz tune && rm -rf tune
