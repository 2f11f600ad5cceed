#!/bin/bash
# d60 (H100 machine, NVIDIA OpenCL 580.159.04): a full search of the evaluation's chunk, group and register
# cap over drops, rubble and sculpt_dense at 0.0625 (the cost the geometric mean of the three scenes'
# count + evaluate). Output: docs/measurements/h100-tune-3scenes.txt, tuning-h100-3scenes.json.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
.device/bn/sdfbrick scene generate sculpt_dense -o /tmp/sculpt_dense.json
.device/bn/sdfbrick -d gpu --tuning-db /tmp/tuned.json tune scenes/drops.json scenes/rubble.json /tmp/sculpt_dense.json \
  --brick-size 0.0625 --kernels evaluate --strategy full --repeat 3 --warmup 1 --json $OUT/d60-tune.json
