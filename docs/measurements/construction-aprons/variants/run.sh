#!/usr/bin/env bash
# Variants of the evaluation kernel (one binary; --kernel-dir .device/khV holds kernels/ with
# EVAL_HOIST forced to V: 2 = primitive and operation once per edit, 1 = primitive only, 0 = once
# per sample) against main before the change (sdfbrick-main), apron sharing from K edits
# (--apron-share-edits K; 0 = off). The closed-form-vs-table files come from an earlier run of the
# same binary in which the shipped kernels computed each owned sample's index by a search over the
# regions (k4) and a kernel directory used the __local table (table).
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick; M=$PWD/.device/bin/sdfbrick-main
O=$OUT/a3; mkdir -p $O
export SDFBRICK_CACHE_DIR=/tmp/sdfcache SDFBRICK_TUNING_DB=$O/tuning.json
R="--brick-size 0.0625 --warmup 1 --repeat 10"
for round in 1 2; do
  for sc in drops rain cubes sculpt; do
    $M -d 0 build scenes/$sc.json $R > $O/$sc-before-$round.txt 2>&1
    for v in 2 1 0; do
      for K in 4 0; do $B --kernel-dir .device/kh$v -d 0 build scenes/$sc.json $R --apron-share-edits $K > $O/$sc-h$v-k$K-$round.txt 2>&1; done
    done
    $B --kernel-dir .device/kh2 -d 0 build scenes/$sc.json $R --apron-share-edits 16 > $O/$sc-h2-k16-$round.txt 2>&1
  done
done
$B --kernel-dir .device/kh2 -d 0 build scenes/drops.json --brick-size 0.0625 --warmup 1 --repeat 3 --kernel-stats > $O/drops-stats.txt 2>&1
$B --kernel-dir .device/kh2 -d 0 build scenes/rain.json --brick-size 0.0625 --warmup 1 --repeat 3 --kernel-stats --apron-share-edits 0 > $O/rain-stats.txt 2>&1
$M -d 0 build scenes/rain.json --brick-size 0.0625 --warmup 1 --repeat 3 --kernel-stats > $O/rain-stats-before.txt 2>&1
