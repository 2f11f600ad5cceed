#!/usr/bin/env bash
# play on the H200 machine (5): a 1,442-operation sculpt log (959 frames) spliced on NVIDIA, whole
# on NVIDIA (split on the one GPU), spliced on PoCL: every frame's brick and list digests compared.
set -u
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/play5; mkdir -p $R
run() { name=$1; shift; echo "== $name: $*" >> $R/log.txt; timeout 280 $B "$@" --json $R/$name.json >> $R/log.txt 2>&1; echo "rc $?" >> $R/log.txt; }
S="play .device/s1k.json --edits .device/s1k.jsonl --frames 959 --brick-size 0.0625 --work construct --digests"
run s1k-gpu -d gpu $S
run s1k-gpu-whole -d gpu --devices split $S
run s1k-pocl -d cpu $S
cd $OUT && tar czf play5.tgz play5 && rm -rf play5
