#!/bin/bash
# PoCL here (2 cores): kz (77b5149's kernels) against kk (the one-sided saturation where the op is a constant), interleaved, three rounds of 3 captures.
B=build/release/host/sdfbrick
for r in 1 2 3; do for sc in drops rubble sculpt; do for k in kz kk; do
  echo "$r $k $sc 0.125: $(timeout 300 $B --kernel-dir .device/$k build scenes/$sc.json --brick-size 0.125 --warmup 1 --repeat 3 2>&1 | grep -oE 'count [0-9.]+|cull [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|digest [0-9a-f]+' | tr '\n' ' ')"
done; done; done
