#!/bin/bash
# d70: the evaluation's prologue. kk: main's kernels (518e082); km: the scales by 2^shift as products
# with exact powers of two instead of ldexp (d69-pow2.diff), and the samples' coordinates from a
# table per axis in __local memory, filled once per brick (one lane only); kn: km with the owned
# samples' table for the shell alone, filled from the mask's popcounts (the interior by formula, the
# owned count by popcounts); kr: kn with the first chunk's edits
# staged before the tables are computed, under their barrier; ks: kn with a binary (sdfbrick-new)
# whose cull counts each word's kept bits in the scan's first pass (scan_popcount_blocks, no
# cull_count). Same digests on PoCL here at 0.125 with --lanes 1 and with lanes. Alternating, two
# rounds of 10 captures; then drops with the H100's compiled-in entry (chunk 32, group 64, 56
# registers), the count with 2 or 4 children a work-item in lanes, per-kernel stats of ks, and ks's
# digests on NVIDIA at 0.125.
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
           "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "scenes/drops.json --brick-size 0.0625 --chunk 32 --group 64 --eval-max-registers 56"; do
    for k in kk km kn kr ks; do
      b=$B; [ $k = ks ] && b=.device/bin/sdfbrick-new
      echo "$r $k $c: $(timeout 40 $b -d gpu --kernel-dir .device/$k build $c $X 2>&1 | ev)"; done
  done
done
# The count with children in lanes on the GPU (--lanes also puts the evaluation in lanes: read the count).
for c in "scenes/drops.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625"; do for l in 1 2 4; do
  echo "lanes $l $c: $(timeout 40 $B -d gpu --kernel-dir .device/kn build $c $X --lanes $l 2>&1 | ev)"; done; done
echo "== ks drops 0.0625 kernel stats"
timeout 40 .device/bin/sdfbrick-new -d gpu --kernel-dir .device/ks build scenes/drops.json --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E "stages|brick_evaluate|edit_prepare"
for d in gpu; do for sc in drops rubble rain board sculpt; do
  echo "$d ks $sc 0.125: $(timeout 60 .device/bin/sdfbrick-new -d $d --kernel-dir .device/ks build scenes/$sc.json --brick-size 0.125 2>&1 | grep -oE 'digest [0-9a-f]+.*')"; done; done
