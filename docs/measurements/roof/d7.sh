#!/bin/bash
# Adaptive builds after the check's multiply-shift divisions and sample-numbered classes, the checked
# parents' re-cull and the kept check samples (sdfbrick) against the binary before them
# (sdfbrick-base, ed6568b), alternating, two rounds: NVIDIA at E = 0.002 (drops and board: 0.03125,
# E = 0.001), PoCL on 16 cores at E = 0.008; uniform builds at the finest sizes; one adaptive build per
# scene on both devices at E = 0.008 and at E = 0.002 with branching 2 (digests across vendors).
source .device/env.sh
R=$OUT/d7; mkdir -p $R
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
S=scenes/stability
X="--warmup 1 --repeat 10 --kernel-stats"
P="--warmup 1 --repeat 3 --kernel-stats"
H="ground_trees engraved_slab grooved_board steep_blends"
for round in 1 2; do
  for v in sdfbrick sdfbrick-base; do
    B=.device/bin/$v
    for n in $H; do
      timeout 100 $B -d gpu build $S/$n.json --tolerance 0.002 $X --json $R/gpu-$n-$v-$round.json > $R/gpu-$n-$v-$round.txt 2>&1
      timeout 100 $B -d cpu build $S/$n.json --tolerance 0.008 $P --json $R/cpu-$n-$v-$round.json > $R/cpu-$n-$v-$round.txt 2>&1
    done
    for n in drops board; do
      timeout 100 $B -d gpu build scenes/$n.json --brick-size 0.03125 --tolerance 0.001 $X --json $R/gpu-$n-$v-$round.json > $R/gpu-$n-$v-$round.txt 2>&1
      timeout 100 $B -d cpu build scenes/$n.json --brick-size 0.0625 --tolerance 0.004 $P --json $R/cpu-$n-$v-$round.json > $R/cpu-$n-$v-$round.txt 2>&1
    done
  done
done
B=.device/bin/sdfbrick
for n in $H; do
  timeout 100 $B -d gpu build $S/$n.json --brick-size 0.015625 $X --json $R/gpu-$n-uniform.json > $R/gpu-$n-uniform.txt 2>&1
  timeout 100 $B -d cpu build $S/$n.json --brick-size 0.0625 $P --json $R/cpu-$n-uniform.json > $R/cpu-$n-uniform.txt 2>&1
  for d in gpu cpu; do
    timeout 100 $B -d $d build $S/$n.json --tolerance 0.008 > $R/digest-$n-$d-e008.txt 2>&1
    timeout 100 $B -d $d build $S/$n.json --tolerance 0.002 --branching 2 > $R/digest-$n-$d-b2.txt 2>&1
  done
done
for n in drops board; do
  timeout 100 $B -d gpu build scenes/$n.json --brick-size 0.03125 $X --json $R/gpu-$n-uniform.json > $R/gpu-$n-uniform.txt 2>&1
  timeout 100 $B -d cpu build scenes/$n.json --brick-size 0.0625 $P --json $R/cpu-$n-uniform.json > $R/cpu-$n-uniform.txt 2>&1
done
grep -H "digest" $R/digest-*.txt > $R/digests.txt
cd $OUT && tar czf d7.tgz d7 && rm -rf d7
