#!/bin/bash
# The count's fold skipping edits that cannot change a child's value (cskip, loaded with
# --kernel-dir) against the embedded kernels, alternating, NVIDIA, 10 captures; digests compared.
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/d6; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
$B scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
$B scene generate stability/edits_65536 -o /tmp/e64k.json > /dev/null 2>&1
X="--warmup 1 --repeat 10"
for round in 1 2; do
  for v in base cskip; do
    K=""; [ $v != base ] && K="--kernel-dir .device/cskip"
    $B -d gpu build /tmp/sculpt_dense.json --brick-size 0.0625 $X $K --json $R/$v-sculpt_dense-$round.json > $R/$v-sculpt_dense-$round.txt 2>&1
    $B -d gpu build /tmp/e64k.json --brick-size 0.0625 $X $K --json $R/$v-e64k-$round.json > $R/$v-e64k-$round.txt 2>&1
    for s in drops sculpt rubble; do
      $B -d gpu build scenes/$s.json --brick-size 0.0625 $X $K --json $R/$v-$s-$round.json > $R/$v-$s-$round.txt 2>&1
    done
  done
done
cd $OUT && tar czf d6.tgz d6 && rm -rf d6
