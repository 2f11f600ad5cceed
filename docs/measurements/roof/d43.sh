#!/bin/bash
# d43: bin = 611105d against bh = HEAD (coarsest leaf level from the rounding, skip records, float4
# cell centre); NVIDIA construction and adaptive builds; PoCL 16-core digests and times.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
X="--warmup 1 --repeat 10"
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|[0-9]+ leaf bricks of [0-9.]+|^  digest [0-9a-f]+' | head -9 | tr '\n' ' '; }
S=scenes/stability
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
.device/bh/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
echo "== construction, 0.0625, alternating"
for sc in "scenes/drops.json" "/tmp/sculpt_dense.json" "scenes/rain.json" "scenes/sculpt.json" "$S/ground_trees.json"; do
  for v in bin bh bin bh; do
    echo "$v $sc: $(timeout 60 .device/$v/sdfbrick -d gpu build $sc --brick-size 0.0625 $X 2>&1 | ev)"
  done
done
echo "== adaptive against uniform at the finest size"
for sc in "$S/engraved_slab.json --tolerance 0.002" "scenes/board.json --brick-size 0.03125 --tolerance 0.001" "$S/ground_trees.json --tolerance 0.002" "$S/grooved_board.json --tolerance 0.002"; do
  for v in bin bh bin bh; do
    out=$(timeout 60 .device/$v/sdfbrick -d gpu build $sc $X 2>&1)
    echo "A $v $sc: $(echo "$out" | ev)"
  done
  f=$(echo "$out" | grep -oE 'leaf bricks of [0-9.]+' | head -1 | grep -oE '[0-9.]+$')
  for v in bin bh; do echo "U $v ${sc%% *} --brick-size $f: $(timeout 60 .device/$v/sdfbrick -d gpu build ${sc%% *} --brick-size $f $X 2>&1 | ev)"; done
done
echo "== chunk and registers"
for sc in "scenes/drops.json" "/tmp/sculpt_dense.json"; do
  for cr in "--chunk 32" "--chunk 32 --eval-max-registers 96" "--eval-max-registers 96"; do
    echo "bh $sc $cr: $(timeout 60 .device/bh/sdfbrick -d gpu build $sc --brick-size 0.0625 $cr $X 2>&1 | ev)"
  done
done
echo "== PoCL 16 cores"
for sc in "$S/engraved_slab.json --brick-size 0.0625" "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "scenes/board.json --brick-size 0.0625" "scenes/board.json --brick-size 0.0625 --tolerance 0.004" "scenes/drops.json --brick-size 0.0625"; do
  for v in bin bh; do echo "pocl $v $sc: $(timeout 100 .device/$v/sdfbrick -d cpu build $sc --warmup 1 --repeat 3 2>&1 | ev)"; done
done
