#!/bin/bash
# d55: the sibling cull at the top levels (bx: bin with the thresholds read from the environment,
# X_FROM parents and X_MIN children a parent; unset: bin's 2 per compute unit and 8) and the
# evaluation's register cap on the current kernels (bin = 54fbe71). NVIDIA, alternating, two rounds.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+' | head -10 | tr '\n' ' '; }
S=scenes/stability
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
.device/bin/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for r in 1 2; do
  for sc in "/tmp/sculpt_dense.json --brick-size 0.0625" "$S/edits_65536.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625" "scenes/drops.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625"; do
    echo "$r bin $sc: $(timeout 60 .device/bin/sdfbrick -d gpu build $sc $X 2>&1 | ev)"
    for fm in "1 1" "1 4" "1 8" "16 1"; do
      set -- $fm
      echo "$r bx from $1 min $2 $sc: $(X_FROM=$1 X_MIN=$2 timeout 60 .device/bx/sdfbrick -d gpu build $sc $X 2>&1 | ev)"
    done
  done
done
for r in 1 2; do
  for sc in "/tmp/sculpt_dense.json --brick-size 0.0625" "scenes/drops.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008"; do
    for g in 0 64 56; do
      echo "$r bin registers $g $sc: $(timeout 60 .device/bin/sdfbrick -d gpu build $sc $X --eval-max-registers $g 2>&1 | ev)"
    done
  done
done
for sc in /tmp/sculpt_dense.json $S/edits_65536.json; do
  echo "== bin $sc"
  timeout 100 .device/bin/sdfbrick -d gpu build $sc --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E '^ +[0-9] |brick_count |cull_'
  echo "== bx 1 1 $sc"
  X_FROM=1 X_MIN=1 timeout 100 .device/bx/sdfbrick -d gpu build $sc --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E '^ +[0-9] |brick_count |cull_'
done
for d in gpu cpu; do echo "bx 1 1 $d drops 0.125: $(X_FROM=1 X_MIN=1 timeout 120 .device/bx/sdfbrick -d $d build scenes/drops.json --brick-size 0.125 2>&1 | ev)"; done
