#!/bin/bash
# The count keeping the root's children without a test where the fold is wide (.device/kkeep, a kernel
# variant: brick_count keeps every child of a level-0 parent) against the kernels of the commit
# before (.device/kcur), both through --kernel-dir: uniform builds of sculpt_dense, edits_65536,
# sculpt and drops at 0.0625 on NVIDIA, 5 captures, two rounds; digests compared.
B=$PWD/.device/bin/sdfbrick
R=$OUT/d24; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 5 --kernel-stats"
$B scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
$B scene generate stability/edits_65536 -o /tmp/edits_65536.json > /dev/null 2>&1
for round in 1 2; do
  for sc in /tmp/sculpt_dense.json /tmp/edits_65536.json scenes/sculpt.json scenes/drops.json; do
    n=$(basename $sc .json)
    for v in kcur kkeep; do
      timeout 120 $B --kernel-dir $PWD/.device/$v -d gpu build $sc --brick-size 0.0625 $X > $R/gpu-$v-$n-$round.txt 2>&1
    done
  done
done
for f in $R/gpu-*-1.txt $R/gpu-*-2.txt; do echo "$(basename $f): $(grep -oE 'total [0-9.]+ ms' $f | head -1) $(grep -oE 'count [0-9.]+, scan' $f | head -1) $(grep -oE 'cull [0-9.]+,' $f | head -1) $(grep -oE '^  digest [0-9a-f]+' $f)"; done
cd $OUT && tar czf d24.tgz d24 && rm -rf d24
