#!/bin/bash
# d78: the adaptive check passing a brick unchecked where its list is one box or rounded box whose
# band-limited field is a plane over the brick's samples (brick_thin's bound: half a quantisation step and the
# rounding). old: 9dcd9b6's binary; new: main's (9740f91 or later). Two rounds of 10 captures, in turn;
# then per-kernel stats of engraved_slab at E = 0.002 (new), and the uniform builds at the finest size.
# Run 2026-12-07 (next session) on an H100: d78.txt. d78-tilted.json is the rotated
# slab of ConstructAdaptive.PlaneBricksPassedUncheckedMeetTheTolerance (rounded).
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
GPU=$(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader); echo "$GPU"
X="--warmup 1 --repeat 10"
S=scenes/stability
ev() { grep -oE '^  geometry [^:]+: [0-9]+ leaf bricks|check [0-9.]+|evaluate [0-9.]+|count [0-9.]+|cull [0-9.]+|order [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+|worst error[^\n]*' | head -12 | tr '\n' ' '; }
for r in 1 2; do
  for c in "$S/engraved_slab.json --tolerance 0.002" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" \
           "$S/grooved_board.json --tolerance 0.002" "$S/ground_trees.json --tolerance 0.002" "$S/steep_blends.json --tolerance 0.002" \
           "scenes/board.json --brick-size 0.03125 --tolerance 0.001" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001" \
           "docs/measurements/roof/d78-tilted.json --brick-size 0.03125 --tolerance 0.002"; do
    for b in sdfbrick sdfbrick-new; do
      echo "$r $b $c: $(timeout 60 .device/bin/$b -d gpu build $c $X 2>&1 | ev)"; done
  done
  for c in "$S/engraved_slab.json --brick-size 0.015625" "$S/engraved_slab.json --brick-size 0.0625"; do
    echo "$r uniform $c: $(timeout 60 .device/bin/sdfbrick-new -d gpu build $c $X 2>&1 | ev)"; done
done
echo "== kernel stats engraved_slab E 0.002 new"
timeout 60 .device/bin/sdfbrick-new -d gpu build $S/engraved_slab.json --tolerance 0.002 $X --kernel-stats 2>&1 | sed -n '/^    level  cell/,$p' | grep -vE "^    level [0-9] .* 0\.00[0-9]{2} *$" | head -110
echo "== kernel stats engraved_slab 0.0625 E 0.008 new"
timeout 60 .device/bin/sdfbrick-new -d gpu build $S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008 $X --kernel-stats 2>&1 | sed -n '/^    level  cell/,$p' | grep -vE "^    level [0-9] .* 0\.00[0-9]{2} *$" | head -80
if echo "$GPU" | grep -q H200; then
  for r in 1 2; do for e in "" "--chunk 32 --group 64 --eval-max-registers 56" "--chunk 32 --group 64"; do
    echo "$r drops 0.0625 $e: $(timeout 60 .device/bin/sdfbrick-new -d gpu build scenes/drops.json --brick-size 0.0625 $e $X 2>&1 | ev)"; done; done
fi
echo "elapsed $SECONDS s"
