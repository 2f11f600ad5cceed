#!/usr/bin/env bash
# play on the H200 machine (2): edit logs on a 65,536-edit and a 4,096-edit sculpt, spliced against
# whole rebuilds (split on the one GPU rebuilds every geometry), bits on NVIDIA and PoCL; drops'
# frames written by the writer threads.
set -u
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/play2; mkdir -p $R
run() { name=$1; shift; echo "== $name: $*" >> $R/log.txt; timeout 150 $B "$@" --json $R/$name.json >> $R/log.txt 2>&1; echo "rc $?" >> $R/log.txt; }
S64="play .device/s64k.json --edits .device/s64k.jsonl --frames 51 --brick-size 0.0625"
S4="play .device/s4k.json --edits .device/s4k.jsonl --frames 61 --brick-size 0.0625"
run s64k-gpu -d gpu $S64 --work bvh
run s64k-gpu-b -d gpu $S64 --work bvh
run s64k-gpu-digests -d gpu $S64 --work bvh --digests
run s64k-gpu-whole -d gpu --devices split $S64 --work bvh
run s64k-gpu-whole-digests -d gpu --devices split $S64 --work bvh --digests
run s64k-gpu-trace -d gpu $S64 --width 1920 --height 1080
run s4k-gpu -d gpu $S4 --work bvh
run s4k-gpu-whole -d gpu --devices split $S4 --work bvh
run s4k-gpu-digests -d gpu $S4 --work bvh --digests
run s4k-pocl-digests -d cpu $S4 --work bvh --digests
run s64k-pocl-digests -d cpu play .device/s64k.json --edits .device/s64k.jsonl --frames 6 --brick-size 0.0625 --work bvh --digests
mkdir -p /tmp/frames
run drops-1080-gpu-out -d gpu play scenes/drops.json --brick-size 0.0625 --width 1920 --height 1080 --frames 100 --fps 144 --out /tmp/frames/%04d.ppm
nproc >> $R/log.txt
cd $OUT && tar czf play2.tgz play2 && rm -rf play2
