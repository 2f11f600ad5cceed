#!/bin/bash
# Accuracy of adaptive builds with the check inside each brick's cell (PoCL here): 480x270 hybrid
# --compare at E = 0.002 (finest 0.015625), branching 4 and 2.
cd /work/main
B=build/release/host/sdfbrick
for b in 4 2; do
  for n in ground_trees engraved_slab grooved_board steep_blends; do
    $B -d cpu render scenes/stability/$n.json --width 480 --height 270 --method hybrid --compare --tolerance 0.002 --branching $b --out /tmp/p1/a.png > /tmp/p1/acc-$n-$b.txt 2>&1
  done
done
$B -d cpu render scenes/board.json --brick-size 0.03125 --compare --width 960 --height 540 --tolerance 0.002 > /tmp/p1/acc-board-4.txt 2>&1
$B -d cpu render scenes/board.json --brick-size 0.03125 --compare --width 960 --height 540 --tolerance 0.001 --branching 2 > /tmp/p1/acc-board-2.txt 2>&1
echo done > /tmp/p1/acc-finished
