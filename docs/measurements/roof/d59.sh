#!/bin/bash
# d59: bx (the count's sphere and capsule folds skipping where they cannot change a child, on d5af3cf)
# against bn (main of 2026-12-07 with kernel stats per level); bin (b95461e) against bn on engraved_slab's
# adaptive build; 10^3 samples with culling on and off; engraved_slab's per-level kernel stats; 10 captures.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+.*' | head -10 | tr '\n' ' '; }
S=scenes/stability
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
.device/bn/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for r in 1 2; do
  for v in bin bn; do echo "$r $v engraved 0.0625 E0.008: $(timeout 30 .device/$v/sdfbrick -d gpu build $S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008 $X 2>&1 | ev)"; done
  for sc in "/tmp/sculpt_dense.json" "scenes/drops.json" "scenes/rubble.json" "scenes/sculpt.json"; do
    for v in bn bx; do echo "$r $v $sc: $(timeout 30 .device/$v/sdfbrick -d gpu build $sc --brick-size 0.0625 $X 2>&1 | ev)"; done
  done
done
for c in "" "--no-cull"; do echo "bn samples 10 $c: $(timeout 30 .device/bn/sdfbrick -d gpu build $S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008 --samples 10 $c 2>&1 | ev)"; done
for t in "" "--tolerance 0.008"; do echo "== bn engraved 0.0625 $t kernel stats"; timeout 30 .device/bn/sdfbrick -d gpu build $S/engraved_slab.json --brick-size 0.0625 $t $X --kernel-stats 2>&1 | grep -E "stages|^  [a-z_]+ +[a-z,]+ +[0-9]+ |^    level|digest"; done
for a in "--brick-size 0.015625" "--tolerance 0.002"; do echo "bn engraved $a: $(timeout 60 .device/bn/sdfbrick -d gpu build $S/engraved_slab.json $a $X 2>&1 | ev)"; done
