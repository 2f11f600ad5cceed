#!/usr/bin/env bash
# play on the H200 machine: drops and rain at 0.0625 (1080p, 4K), NVIDIA whole and split, PoCL.
set -u
source .device/env.sh
B=.device/bin/sdfbrick
R=$OUT/play; mkdir -p $R
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader > $R/gpu.txt 2>&1
$B devices > $R/devices.txt 2>&1
run() { name=$1; shift; echo "== $name: $*" >> $R/log.txt; /usr/bin/time -v $B "$@" --json $R/$name.json >> $R/log.txt 2>$R/$name.time; echo "rc $?" >> $R/log.txt; }
run drops-1080-gpu -d gpu play scenes/drops.json --brick-size 0.0625 --width 1920 --height 1080 --frames 300 --fps 144
run rain-1080-gpu -d gpu play scenes/rain.json --brick-size 0.0625 --width 1920 --height 1080 --frames 300 --fps 144
run drops-4k-gpu -d gpu play scenes/drops.json --brick-size 0.0625 --width 3840 --height 2160 --frames 300 --fps 90
run drops-1080-gpu-split -d gpu --devices split play scenes/drops.json --brick-size 0.0625 --width 1920 --height 1080 --frames 200 --fps 144
run drops-1080-gpu-digests -d gpu play scenes/drops.json --brick-size 0.0625 --width 1920 --height 1080 --frames 100 --fps 144 --digests
mkdir -p /tmp/frames
run drops-1080-gpu-out -d gpu play scenes/drops.json --brick-size 0.0625 --width 1920 --height 1080 --frames 100 --fps 144 --out /tmp/frames/%04d.ppm
run drops-1080-gpu-shaded -d gpu play scenes/drops.json --brick-size 0.0625 --width 1920 --height 1080 --frames 100 --fps 144 --mode shaded
run drops-1080-pocl -d cpu play scenes/drops.json --brick-size 0.0625 --width 1920 --height 1080 --frames 8 --fps 144 --digests
run drops-1080-gpu-8 -d gpu play scenes/drops.json --brick-size 0.0625 --width 1920 --height 1080 --frames 8 --fps 144 --digests
run rain-1080-pocl -d cpu play scenes/rain.json --brick-size 0.0625 --width 1920 --height 1080 --frames 8 --fps 144
ls /tmp/frames | wc -l >> $R/log.txt
# the same scene as one render for comparison (wall per capture)
$B -d gpu render scenes/drops.json --brick-size 0.0625 --width 1920 --height 1080 --repeat 10 --json $R/render-1080.json > $R/render-1080.txt 2>&1
cd $OUT && tar czf play.tgz play && rm -rf play
