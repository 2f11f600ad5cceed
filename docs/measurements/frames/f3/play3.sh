#!/usr/bin/env bash
# play on the H200 machine (3): the edit log on a 65,528-edit sculpt (65,208 edits before it), spliced
# against whole rebuilds, bits on NVIDIA and PoCL.
set -u
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/play3; mkdir -p $R
run() { name=$1; shift; echo "== $name: $*" >> $R/log.txt; timeout 200 $B "$@" --json $R/$name.json >> $R/log.txt 2>&1; echo "rc $?" >> $R/log.txt; }
S64="play .device/s64k.json --edits .device/s64k.jsonl --frames 51 --brick-size 0.0625"
run s64k-gpu -d gpu $S64 --work bvh
run s64k-gpu-b -d gpu $S64 --work bvh
run s64k-gpu-digests -d gpu $S64 --work bvh --digests
run s64k-gpu-whole -d gpu --devices split $S64 --work bvh
run s64k-gpu-whole-digests -d gpu --devices split $S64 --work bvh --digests
run s64k-gpu-trace -d gpu $S64 --width 1920 --height 1080
run s64k-pocl-digests -d cpu play .device/s64k.json --edits .device/s64k.jsonl --frames 5 --brick-size 0.0625 --work bvh --digests
cd $OUT && tar czf play3.tgz play3 && rm -rf play3
