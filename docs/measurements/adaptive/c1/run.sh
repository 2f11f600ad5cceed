#!/bin/bash
# PoCL here: adaptive builds with the check inside each brick's cell (embedded) against the check
# before (--kernel-dir /tmp/kold), alternating, two rounds; uniform at 0.0625 beside them.
cd /work/main
B=build/release/host/sdfbrick
R=/tmp/p1
S=scenes/stability
for round in 1 2; do
  for n in ground_trees engraved_slab grooved_board steep_blends drops board; do
    f=$S/$n.json; a="--brick-size 0.0625 --tolerance 0.008"
    case $n in drops|board) f=scenes/$n.json; a="--brick-size 0.0625 --tolerance 0.004";; esac
    $B --kernel-dir /tmp/kold -d cpu build $f $a --warmup 1 --repeat 3 > $R/old-$n-$round.txt 2>&1
    $B -d cpu build $f $a --warmup 1 --repeat 3 > $R/new-$n-$round.txt 2>&1
    [ $round = 1 ] && $B -d cpu build $f --brick-size 0.0625 --warmup 1 --repeat 3 > $R/uniform-$n.txt 2>&1
  done
done
echo done > $R/finished
