#!/bin/bash
# d63: kernel variants loaded with --kernel-dir into one binary (the host of this commit, which asks
# for the skip tests in any geometry with adds or subtracts on one lane), alternating, two rounds of
# 10 captures: ko, the kernels before this session (3c5a36f); kn, explicit fma in the field's sums of
# squares, rotations and smooth terms (ac16d34); kx, kn with the work-item's extremes computed only
# after a folded edit (a8b52a3); ky, kx with the work-item test for every primitive (item_far). Then
# ky's digests on NVIDIA and PoCL at 0.125, and drops' kernel stats with ky.
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
           "scenes/sculpt.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "$S/edits_65536.json --brick-size 0.0625" \
           "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "$S/ground_trees.json --brick-size 0.0625"; do
    for k in ko kn kx ky; do echo "$r $k $c: $(timeout 40 $B -d gpu --kernel-dir .device/$k build $c $X 2>&1 | ev)"; done
  done
done
for d in gpu cpu; do for sc in scenes/drops.json scenes/rubble.json scenes/rain.json; do
  echo "$d ky $sc 0.125: $(timeout 60 $B -d $d --kernel-dir .device/ky build $sc --brick-size 0.125 2>&1 | grep -oE 'digest [0-9a-f]+.*')"; done; done
echo "== ky drops 0.0625 kernel stats"; timeout 40 $B -d gpu --kernel-dir .device/ky build scenes/drops.json --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E "stages|^  [a-z_]+ +[a-z,]+ +[0-9]+ |^    level|digest"
