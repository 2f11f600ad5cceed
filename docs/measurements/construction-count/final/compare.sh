#!/usr/bin/env bash
# Accuracy after the change: drops at 0.0625, 1920 x 1080, normals, sphere method, against the
# double-precision reference (render --compare) on the H200, as in construction-lanes/h200x2.
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick
O=$OUT/compare; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=$O/tuning.json
$B -d 0 render scenes/drops.json --brick-size 0.0625 --width 1920 --height 1080 --mode normals --method sphere \
  --compare --out /tmp/drops.ppm --json $O/after-compare.json > $O/after-compare.txt 2>&1
cat $O/after-compare.txt
cd $OUT && tar czf compare.tgz compare && rm -rf compare
