#!/bin/bash
# The check's work-group on NVIDIA: the evaluation's (the tuned group, the default) against 128 and
# 256 work-items, set through an environment variable of an experimental binary (sdfbrick-exp),
# alternating, two rounds; adaptive builds of d8 at E = 0.002 (drops and board: 0.03125, E = 0.001).
source .device/env.sh
R=$OUT/d11; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
S=scenes/stability
B=.device/bin/sdfbrick-exp
X="--warmup 1 --repeat 10 --kernel-stats"
for round in 1 2; do
  for g in default 128 256; do
    for n in ground_trees engraved_slab grooved_board steep_blends drops board; do
      f=$S/$n.json; a="--tolerance 0.002"
      case $n in drops|board) f=scenes/$n.json; a="--brick-size 0.03125 --tolerance 0.001";; esac
      if [ $g = default ]; then unset SDFBRICK_CHECK_GROUP; else export SDFBRICK_CHECK_GROUP=$g; fi
      timeout 100 $B -d gpu build $f $a $X --json $R/gpu-$n-$g-$round.json > $R/gpu-$n-$g-$round.txt 2>&1
    done
  done
done
cd $OUT && tar czf d11.tgz d11 && rm -rf d11
