#!/bin/bash
# d80: the adaptive check's levels with few candidates (at most two waves by the occupancy model) with
# twice the work-items a brick, in the candidates' evaluation and in brick_check. old: 948f9e9's
# behaviour (d79's experimental binary, no variables set); new: main (ad692b7 or later: the same
# kernels and rules). Two rounds of 10 captures, in turn, with the uniform builds at the finest size
# beside them; then per-level stats, every kernel of engraved_slab uniform against adaptive, the leaf
# evaluation of small builds with --group 128, and on an H200 the evaluation's tuning entry searched
# again. Prepared 2026-12-07; not run: no device machine came on 2026-12-07 after d79, nor on
# 2026-12-08 (eleven requests, then lending paused). Needs .device/bin/sdfbrick-exp (d79-groups.diff
# on 948f9e9) and .device/bin/sdfbrick-new (main's device build).
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
GPU=$(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader); echo "$GPU"
X="--warmup 1 --repeat 10"
S=scenes/stability
ev() { grep -oE 'check [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+' | tr '\n' ' '; }
ks() { awk '/^  (brick_evaluate|brick_check) /{p=1; print; next} /^  [a-z_]+ /{p=0} p&&/^    level/{print}'; }
for r in 1 2; do
  for c in "$S/engraved_slab.json --tolerance 0.002" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" \
           "$S/grooved_board.json --tolerance 0.002" "$S/ground_trees.json --tolerance 0.002" "$S/steep_blends.json --tolerance 0.002" \
           "scenes/board.json --brick-size 0.03125 --tolerance 0.001" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001" \
           "scenes/board.json --tolerance 0.004" "scenes/drops.json --tolerance 0.004"; do
    for b in sdfbrick-exp sdfbrick-new; do
      echo "$r $b $c: $(timeout 60 .device/bin/$b -d gpu build $c $X 2>&1 | ev)"; done
  done
  for c in "$S/engraved_slab.json --brick-size 0.015625" "$S/engraved_slab.json --brick-size 0.0625"; do
    echo "$r uniform $c: $(timeout 60 .device/bin/sdfbrick-new -d gpu build $c $X 2>&1 | ev)"; done
done
for c in "$S/engraved_slab.json --tolerance 0.002" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008"; do
  echo "== new $c"; timeout 60 .device/bin/sdfbrick-new -d gpu build $c $X --kernel-stats 2>&1 | ks
done
for r in 1 2; do for c in "scenes/drops.json --brick-size 0.0625" "scenes/sculpt_dense.json --brick-size 0.0625"; do
  echo "$r uniform $c: $(timeout 60 .device/bin/sdfbrick-new -d gpu build $c $X 2>&1 | grep -oE 'evaluate [0-9.]+|count [0-9.]+|cull [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+' | tr '\n' ' ')"; done; done
echo "elapsed $SECONDS s"
# Where the adaptive build's time goes beside the check: every kernel, uniform against adaptive.
for c in "$S/engraved_slab.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008"; do
  echo "== all kernels, new $c"; timeout 60 .device/bin/sdfbrick-new -d gpu build $c $X --kernel-stats 2>&1 | grep -vE '^    level'
done
# The leaf evaluation of small builds with twice the work-items a brick (--group 128: the whole
# evaluation's group; the leaves are the last level of brick_evaluate's lines).
for c in "$S/engraved_slab.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" \
         "$S/engraved_slab.json --tolerance 0.002" "$S/steep_blends.json --tolerance 0.002"; do
  for g in "" "--group 128"; do
    o=$(timeout 60 .device/bin/sdfbrick-new -d gpu build $c $X $g --kernel-stats 2>&1)
    echo "== new $g $c: $(echo "$o" | ev)"; echo "$o" | ks
  done
done
# On an H200 only: the evaluation's entry searched again with these kernels (as d64 on the H100).
if echo "$GPU" | grep -q H200; then
  timeout 330 .device/bin/sdfbrick-new -d gpu --tuning-db /tmp/tuned.json tune scenes/drops.json scenes/rubble.json \
    scenes/sculpt_dense.json --brick-size 0.0625 --kernels evaluate --strategy full --repeat 3 --warmup 1 --json $OUT/d80-tune.json
  echo "elapsed $SECONDS s"
fi
