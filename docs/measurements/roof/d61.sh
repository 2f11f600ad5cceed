#!/bin/bash
# d61 (the same H100, warm): the compiled-in H100 entry (chunk 16, group 64) against d60's winner
# (chunk 32, group 64, registers 56) and the cap alone, two rounds of 10 captures.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
ev() { grep -oE 'tuning: .*|count [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+' | head -8 | tr '\n' ' '; }
for r in 1 2; do for sc in /tmp/sculpt_dense.json scenes/drops.json scenes/rubble.json scenes/sculpt.json scenes/stability/edits_65536.json; do
  for a in "" "--chunk 32 --group 64 --eval-max-registers 56" "--chunk 16 --group 64 --eval-max-registers 56"; do
    echo "$r $sc [$a]: $(timeout 40 .device/bn/sdfbrick -d gpu build $sc --brick-size 0.0625 $a --warmup 1 --repeat 10 2>&1 | ev)"
  done; done; done
