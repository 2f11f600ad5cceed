#!/bin/bash
# d54: as d53, bin = bb7eda2's binary, with the edits' reaches kept beside the prepared edits (the cull reads
# no SdfEdit) against bo = 848d7c0's, alternating, on NVIDIA: drops,
# sculpt_dense and rubble at 0.0625 (two rounds, 10 captures each); engraved_slab adaptive (0.0625,
# tolerance 0.008) and uniform 0.0625 on NVIDIA and on PoCL (16 cores); digests across devices.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+' | head -10 | tr '\n' ' '; }
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
.device/bin/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
for r in 1 2; do
  for sc in "scenes/drops.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625"; do
    for v in bo bin; do echo "$v gpu $sc: $(timeout 60 .device/$v/sdfbrick -d gpu build $sc --warmup 1 --repeat 10 2>&1 | ev)"; done
  done
done
E=scenes/stability/engraved_slab.json
for d in gpu cpu; do
  R="--warmup 1 --repeat 10"; [ $d = cpu ] && R="--warmup 1 --repeat 3"
  for r in 1 2; do
    for v in bo bin; do
      echo "$v $d engraved uniform 0.0625: $(timeout 120 .device/$v/sdfbrick -d $d build $E --brick-size 0.0625 $R 2>&1 | ev)"
      echo "$v $d engraved adaptive 0.0625 E0.008: $(timeout 120 .device/$v/sdfbrick -d $d build $E --brick-size 0.0625 --tolerance 0.008 $R 2>&1 | ev)"
    done
  done
done
for d in cpu gpu; do echo "bin $d drops 0.125: $(timeout 120 .device/bin/sdfbrick -d $d build scenes/drops.json --brick-size 0.125 2>&1 | ev)"; done
