#!/bin/bash
# d52: how much the two divisions of sdf_prepare cost the evaluation's staging: kp (a timing probe
# whose sdf_prepare multiplies instead: wrong values and digests) against kn (848d7c0), both through
# --kernel-dir into the 1c907e1 binary; and kn with a 64-register cap. NVIDIA, two rounds.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+' | head -10 | tr '\n' ' '; }
S=scenes/stability
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
.device/bn/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for sc in "scenes/drops.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625"; do
  for v in kn kp kn kp; do
    echo "$v $sc: $(timeout 60 .device/bn/sdfbrick -d gpu --kernel-dir .device/$v build $sc $X 2>&1 | ev)"
  done
  for r in 64 56; do echo "kn registers $r $sc: $(timeout 60 .device/bn/sdfbrick -d gpu --kernel-dir .device/kn build $sc $X --eval-max-registers $r 2>&1 | ev)"; done
done
