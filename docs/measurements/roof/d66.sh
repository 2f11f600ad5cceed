#!/bin/bash
# d66: `old` (d65's binary without its knobs: cull_write a word a work-item at the leaves, kz's
# kernels) against `w4` (this commit's host: cull_write at most 4 bits a work-item on GPUs, kz's
# kernels) and `new` (this commit: w4 with kk, the one-sided saturation where the op is a
# constant). Alternating, two rounds of 10 captures; then kk's digests on NVIDIA and PoCL, and
# drops' kernel stats and roofline with this commit.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
X="--warmup 1 --repeat 10"
S=scenes/stability
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+.*' | head -10 | tr '\n' ' '; }
.device/bin/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
run() { echo "$1 $4: $(timeout 40 .device/bin/$2 -d gpu --kernel-dir .device/$3 build $4 $X 2>&1 | ev)"; }
for r in 1 2; do
  for c in "scenes/drops.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" \
           "scenes/sculpt.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "scenes/board.json --brick-size 0.03125" \
           "$S/edits_65536.json --brick-size 0.0625" "$S/ground_trees.json --brick-size 0.0625" \
           "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001"; do
    run "$r old" sdfbrick-exp kz "$c"
    run "$r w4" sdfbrick kz "$c"
    run "$r new" sdfbrick kk "$c"
  done
done
for d in gpu cpu; do for sc in scenes/drops.json scenes/rubble.json scenes/rain.json scenes/board.json; do
  echo "$d new $sc 0.125: $(timeout 60 .device/bin/sdfbrick -d $d build $sc --brick-size 0.125 2>&1 | grep -oE 'digest [0-9a-f]+.*')"; done; done
echo "== new drops 0.0625 kernel stats"
timeout 40 .device/bin/sdfbrick -d gpu build scenes/drops.json --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E "stages|total over|^  [a-z_]+ +[a-z,]+ +[0-9]+ |^    level|digest"
timeout 120 .device/bin/sdfbrick -d gpu devices --peaks 2>&1 | grep peaks
timeout 60 .device/bin/sdfbrick -d gpu build scenes/drops.json --brick-size 0.0625 $X 2>&1 | grep -A6 "roofline"
timeout 60 .device/bin/sdfbrick -d gpu build /tmp/sculpt_dense.json --brick-size 0.0625 $X 2>&1 | grep -A6 "roofline"
