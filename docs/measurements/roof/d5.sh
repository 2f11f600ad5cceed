#!/bin/bash
# The count stage split over several work-groups per parent at the top levels (sdfbrick) against the
# binary before it (sdfbrick-base), alternating, NVIDIA, 10 captures; digests compared.
source .device/env.sh
R=$OUT/d5; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
.device/bin/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
.device/bin/sdfbrick scene generate stability/edits_65536 -o /tmp/e64k.json > /dev/null 2>&1
X="--warmup 1 --repeat 10 --kernel-stats"
for round in 1 2; do
  for b in sdfbrick sdfbrick-base; do
    B=.device/bin/$b
    $B -d gpu build /tmp/sculpt_dense.json --brick-size 0.0625 $X --json $R/$b-sculpt_dense-$round.json > $R/$b-sculpt_dense-$round.txt 2>&1
    $B -d gpu build /tmp/e64k.json --brick-size 0.0625 $X --json $R/$b-e64k-$round.json > $R/$b-e64k-$round.txt 2>&1
    for s in drops sculpt rain rubble; do
      $B -d gpu build scenes/$s.json --brick-size 0.0625 $X --json $R/$b-$s-$round.json > $R/$b-$s-$round.txt 2>&1
    done
    $B -d gpu build scenes/drops.json --brick-size 0.03125 --tolerance 0.001 $X --json $R/$b-drops-adaptive-$round.json > $R/$b-drops-adaptive-$round.txt 2>&1
  done
done
.device/bin/sdfbrick -d cpu build /tmp/e64k.json --brick-size 0.0625 --json $R/pocl-e64k.json > $R/pocl-e64k.txt 2>&1
for s in 2 4 8; do
  .device/bin/sdfbrick -d gpu build /tmp/sculpt_dense.json --brick-size 0.0625 --count-splits $s --warmup 1 --repeat 5 --json $R/sculpt_dense-splits$s.json > $R/sculpt_dense-splits$s.txt 2>&1
done
cd $OUT && tar czf d5.tgz d5 && rm -rf d5
