#!/bin/bash
# Kernels of 137639a (float3 cell centre) against HEAD's (float4), alternating, medians of 3.
# The old kernels: mkdir /tmp/kold && git archive 137639a kernels | tar -x -C /tmp/kold
B=build/release/host/sdfbrick
S=scenes/stability
for r in 1 2; do
  for a in "scenes/board.json --brick-size 0.015625" "scenes/board.json --tolerance 0.002" "$S/engraved_slab.json --brick-size 0.015625" "scenes/drops.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "$S/ground_trees.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625"; do
    for kd in "--kernel-dir /tmp/kold/kernels" ""; do
      echo "$r [${kd:+old}${kd:-new}] $a: $(timeout 300 $B $kd build $a --warmup 1 --repeat 3 2>&1 | grep -oE 'stages.*|^  digest [0-9a-f]+' | sed -E 's/setup.*//; s/(scan|subdivide|order|aabb) [0-9.]+, //g' | tr '\n' ' ')"
    done
  done
done
