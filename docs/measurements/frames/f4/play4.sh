#!/usr/bin/env bash
# play on the H200 machine (4): after the per-frame uploads and scratch came from the device's pool.
# drops and rain at 0.0625 (1080p, 4K), and the 64k sculpt session spliced.
set -u
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/play4; mkdir -p $R
run() { name=$1; shift; echo "== $name: $*" >> $R/log.txt; timeout 150 $B "$@" --json $R/$name.json >> $R/log.txt 2>&1; echo "rc $?" >> $R/log.txt; }
run drops-1080-gpu -d gpu play scenes/drops.json --brick-size 0.0625 --width 1920 --height 1080 --frames 300 --fps 144
run rain-1080-gpu -d gpu play scenes/rain.json --brick-size 0.0625 --width 1920 --height 1080 --frames 300 --fps 144
run drops-4k-gpu -d gpu play scenes/drops.json --brick-size 0.0625 --width 3840 --height 2160 --frames 300 --fps 90
run drops-1080-gpu-b -d gpu play scenes/drops.json --brick-size 0.0625 --width 1920 --height 1080 --frames 300 --fps 144
run s64k-gpu -d gpu play .device/s64k.json --edits .device/s64k.jsonl --frames 56 --brick-size 0.0625 --work bvh
cd $OUT && tar czf play4.tgz play4 && rm -rf play4
