#!/bin/bash
# Where drops' evaluation time goes (timing only, wrong bits except "shipped"): the kernels loaded
# with --kernel-dir, each with one part more removed; then the shipped kernel at chunks 16, 32, 64.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
B=.device/bnew/sdfbrick
ev() { grep -oE 'evaluate [0-9.]+|total [0-9.]+ ms' | head -2 | tr '\n' ' '; }
for round in 1 2; do
  for k in shipped k_test k_none k_noprep k_nofold k_nostage k_nochunk; do
    kd=""; [ $k != shipped ] && kd="--kernel-dir .device/$k"
    echo "$round drops $k: $($B -d gpu $kd build scenes/drops.json --brick-size 0.0625 $X 2>&1 | ev)"
  done
  for c in 16 32 64 128; do
    echo "$round drops chunk $c: $($B -d gpu build scenes/drops.json --brick-size 0.0625 --chunk $c $X 2>&1 | ev)"
  done
  for g in 32 64 128; do
    echo "$round drops group $g: $($B -d gpu build scenes/drops.json --brick-size 0.0625 --group $g $X 2>&1 | ev)"
  done
done
$B -d gpu build scenes/drops.json --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E 'brick_evaluate|digest'
$B -d gpu --kernel-dir .device/k_none build scenes/drops.json --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E 'brick_evaluate'
$B -d gpu --kernel-dir .device/k_nochunk build scenes/drops.json --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E 'brick_evaluate'
