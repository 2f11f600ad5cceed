#!/bin/bash
# d68: c22f797's binary with its kernels (kk) against kh: kk whose hoisted folds are branched once
# per edit on whether it blends, so the per-value test leaves the loop (sdf_combine_hoisted).
# Alternating, two rounds of 10 captures; kh's digests on NVIDIA and PoCL at 0.125.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
X="--warmup 1 --repeat 10"
S=scenes/stability
B=.device/bin/sdfbrick
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+.*' | head -10 | tr '\n' ' '; }
$B scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for r in 1 2; do
  for c in "scenes/drops.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" \
           "scenes/sculpt.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "scenes/board.json --brick-size 0.03125" \
           "$S/edits_65536.json --brick-size 0.0625" "$S/ground_trees.json --brick-size 0.0625" \
           "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001"; do
    for k in kk kh; do echo "$r $k $c: $(timeout 40 $B -d gpu --kernel-dir .device/$k build $c $X 2>&1 | ev)"; done
  done
done
for d in gpu cpu; do for sc in drops rubble rain board sculpt; do
  echo "$d kh $sc 0.125: $(timeout 60 $B -d $d --kernel-dir .device/kh build scenes/$sc.json --brick-size 0.125 2>&1 | grep -oE 'digest [0-9a-f]+.*')"; done; done
