#!/bin/bash
# d56: cull_mark_siblings with a parent's work-groups following its list's length (bw: the change,
# with the thresholds read from the environment as d55's bx: X_FROM parents, X_MIN children a parent;
# unset: 2 per compute unit and 8) against bin (54fbe71), alternating, two rounds of 10 captures.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+.*' | head -10 | tr '\n' ' '; }
S=scenes/stability
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
.device/bin/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for r in 1 2; do
  for sc in "/tmp/sculpt_dense.json --brick-size 0.0625" "$S/edits_65536.json --brick-size 0.0625" "scenes/sculpt.json --brick-size 0.0625" "scenes/drops.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001"; do
    echo "$r bin $sc: $(timeout 60 .device/bin/sdfbrick -d gpu build $sc $X 2>&1 | ev)"
    for fm in "def def" "1 1" "1 4" "1 8"; do
      set -- $fm
      if [ $1 = def ]; then
        echo "$r bw default $sc: $(timeout 60 .device/bw/sdfbrick -d gpu build $sc $X 2>&1 | ev)"
      else
        echo "$r bw from $1 min $2 $sc: $(X_FROM=$1 X_MIN=$2 timeout 60 .device/bw/sdfbrick -d gpu build $sc $X 2>&1 | ev)"
      fi
    done
  done
done
for sc in /tmp/sculpt_dense.json $S/edits_65536.json; do
  echo "== bw default $sc"
  timeout 100 .device/bw/sdfbrick -d gpu build $sc --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E '^ +[0-9] |brick_count |cull_|sibling'
  echo "== bw 1 1 $sc"
  X_FROM=1 X_MIN=1 timeout 100 .device/bw/sdfbrick -d gpu build $sc --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E '^ +[0-9] |brick_count |cull_|sibling'
done
for d in gpu cpu; do echo "bw 1 1 $d drops 0.125: $(X_FROM=1 X_MIN=1 timeout 120 .device/bw/sdfbrick -d $d build scenes/drops.json --brick-size 0.125 2>&1 | ev)"; done
echo "bw default cpu engraved E0.008: $(timeout 120 .device/bw/sdfbrick -d cpu build $S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008 --warmup 1 --repeat 3 2>&1 | ev)"
echo "bin cpu engraved E0.008: $(timeout 120 .device/bin/sdfbrick -d cpu build $S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008 --warmup 1 --repeat 3 2>&1 | ev)"
# the evaluation's full search with the register cap (registers 0, 64, 56, 48) on this device
timeout 300 .device/bw/sdfbrick -d gpu --tuning-db $OUT/tuning-eval.json tune scenes/drops.json --brick-size 0.0625 --kernels evaluate --repeat 5 --budget 120 --json $OUT/tune-eval-report.json 2>&1 | tee $OUT/tune-eval.txt | tail -8
for sc in "/tmp/sculpt_dense.json" "scenes/drops.json" "scenes/rubble.json"; do
  for db in none tuned; do
    T=""; [ $db = tuned ] && T="--tuning-db $OUT/tuning-eval.json"
    echo "bw $db $sc: $(timeout 60 .device/bw/sdfbrick -d gpu $T build $sc --brick-size 0.0625 $X 2>&1 | ev)"
  done
done
