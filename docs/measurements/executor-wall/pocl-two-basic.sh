#!/usr/bin/env bash
# Two one-core PoCL devices (POCL_DEVICES="basic basic") against one, on the 2-core build machine:
# construction and a 1280 x 720 trace of drops and rain at 0.125, alternating, two rounds of one
# warm-up and three captures.
set -uo pipefail
B=${1:-build/release/host/sdfbrick}; O=${2:-/tmp/pocl-two}; mkdir -p $O
export POCL_DEVICES="basic basic" SDFBRICK_RATES=off
for sc in drops rain; do $B --device 0 build scenes/$sc.json --brick-size 0.125 >/dev/null; $B --device cpu --devices split build scenes/$sc.json --brick-size 0.125 >/dev/null; done
for round in 1 2; do for sc in drops rain; do
  $B --device 0 build scenes/$sc.json --brick-size 0.125 --warmup 1 --repeat 3 --json $O/one-build-$sc-$round.json > /dev/null
  $B --device cpu --devices split build scenes/$sc.json --brick-size 0.125 --warmup 1 --repeat 3 --json $O/two-build-$sc-$round.json > /dev/null
  $B --device 0 render scenes/$sc.json --brick-size 0.125 --width 1280 --height 720 --warmup 1 --repeat 3 --out $O/one-$sc.ppm --json $O/one-render-$sc-$round.json > /dev/null
  $B --device cpu --devices split render scenes/$sc.json --brick-size 0.125 --width 1280 --height 720 --warmup 1 --repeat 3 --out $O/two-$sc.ppm --json $O/two-render-$sc-$round.json > /dev/null
done; done
