#!/bin/bash
# d79: the check's work-groups at levels with few candidates (latency: a level's time is its longest
# list's). Experimental binary (EXP_EG: the candidates' evaluation group; EXP_CG: brick_check's
# group; EXP_R / EXP_CR: double them while bricks x group x 2 <= R; d79-groups.diff). Per-level kernel stats.
# Second part: .device/kv holds kernels/ with d79-kv.diff applied. Run 2026-12-07 on an H100: d79.txt.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
GPU=$(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader); echo "$GPU"
S=scenes/stability
X="--warmup 1 --repeat 10 --kernel-stats"
ks() { awk '/^  (brick_evaluate|brick_check) /{p=1; print; next} /^  [a-z_]+ /{p=0} p&&/^    level/{print} /total over/{print} /^  digest/{print}'; }
for r in 1 2; do
  for c in "$S/engraved_slab.json --tolerance 0.002" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" \
           "$S/grooved_board.json --tolerance 0.002" "$S/ground_trees.json --tolerance 0.002" "$S/steep_blends.json --tolerance 0.002" \
           "scenes/board.json --brick-size 0.03125 --tolerance 0.001" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001"; do
    for v in "" "EXP_EG=128 EXP_CG=256" "EXP_EG=256 EXP_CG=512" "EXP_EG=512 EXP_CG=128"; do
      echo "== $r [$v] $c"
      env $v timeout 60 .device/bin/sdfbrick-exp -d gpu build $c $X 2>&1 | ks
    done
  done
done
echo "elapsed $SECONDS s"
echo "== evaluation: each work-item's values consecutive owned samples (kv) against main's kernels"
for r in 1 2; do
  for c in "scenes/drops.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "scenes/sculpt_dense.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625" \
           "scenes/stability/ground_trees.json --brick-size 0.0625" "scenes/stability/engraved_slab.json --brick-size 0.0625" \
           "scenes/board.json --brick-size 0.03125" "scenes/cubes.json --brick-size 0.03125" "scenes/gears.json --brick-size 0.03125" \
           "scenes/stability/steep_blends.json --brick-size 0.03125" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001"; do
    for k in kernels .device/kv; do
      echo "$r $k $c: $(timeout 60 .device/bin/sdfbrick-exp -d gpu build $c --warmup 1 --repeat 10 --kernel-dir $k 2>&1 | grep -oE 'evaluate [0-9.]+|total [0-9.]+ ms|digest [0-9a-f]+ ' | tr '\n' ' ')"
    done
  done
done
echo "elapsed $SECONDS s"
