#!/bin/bash
# The evaluation with its folds compiled for the geometry's primitives alone: where drops' time goes
# now (timing-only kernels through --kernel-dir), and register caps for brick_evaluate
# (-cl-nv-maxrregcount through an experiment binary's EVAL_REGS; none = the shipped options).
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
B=.device/breg/sdfbrick
ev() { grep -oE 'evaluate [0-9.]+|total [0-9.]+ ms|^  digest [0-9a-f]+' | head -3 | tr '\n' ' '; }
$B scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for round in 1 2; do
  for k in k_test k_none k_nofold; do
    echo "$round drops $k: $($B -d gpu --kernel-dir .device/$k build scenes/drops.json --brick-size 0.0625 $X 2>&1 | ev)"
  done
  for sc in "scenes/drops.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001"; do
    for r in none 64 56 48; do
      if [ $r = none ]; then unset EVAL_REGS; else export EVAL_REGS=$r; fi
      echo "$round $sc regs $r: $($B -d gpu build $sc $X 2>&1 | ev)"
    done
    unset EVAL_REGS
  done
done
for r in none 64 56; do
  if [ $r = none ]; then unset EVAL_REGS; else export EVAL_REGS=$r; fi
  $B -d gpu build scenes/drops.json --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E 'brick_evaluate'
done
