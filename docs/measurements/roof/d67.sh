#!/bin/bash
# d67: how fast the evaluation folds when it folds every counted step: drops and sculpt_dense at
# 0.0625 with and without --no-skip-far (c22f797's binary), 10 captures, two rounds alternating,
# with the roofline (peaks measured first).
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
B=.device/bin/sdfbrick
X="--warmup 1 --repeat 10"
$B scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
timeout 120 $B -d gpu devices --peaks 2>&1 | grep peaks
for r in 1 2; do for sc in scenes/drops.json /tmp/sculpt_dense.json; do for f in "" "--no-skip-far"; do
  echo "== $r $sc $f"
  timeout 90 $B -d gpu build $sc --brick-size 0.0625 $f $X 2>&1 | grep -E "stages|evaluate +[0-9.]+ ms|digest"
done; done; done
# The programs NVIDIA compiled (PTX in the on-disk cache), to read the evaluation's inner loop.
tar czf $OUT/d67-cache.tgz -C /tmp sdfcache && ls -la /tmp/sdfcache | head -30
