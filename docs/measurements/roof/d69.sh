#!/bin/bash
# d69 (prepared, not run: the session's device time was spent): the evaluation's scales by 2^shift
# as products with an exact power of two instead of ldexp (d69-pow2.diff; the same digests on PoCL
# here at 0.125, uniform and adaptive, drops and board). kk: the kernels of main; kl: with the diff.
# NVIDIA's PTX of the evaluation (d67's program cache) has 138 of its about 430 instructions before
# the edit loop, in several branches, in the three ldexp.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
nvidia-smi --query-gpu=name --format=csv,noheader
B=.device/bin/sdfbrick
ev() { grep -oE 'evaluate [0-9.]+|total [0-9.]+ ms|^  digest [0-9a-f]+' | tr '\n' ' '; }
for r in 1 2; do for c in "scenes/drops.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625"; do
  for k in kk kl; do echo "$r $k $c: $(timeout 30 $B -d gpu --kernel-dir .device/$k build $c --warmup 1 --repeat 10 2>&1 | ev)"; done
done; done
