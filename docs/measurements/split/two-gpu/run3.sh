#!/usr/bin/env bash
# Run 3 (two H200s): one GPU against two in split mode at 0.03125 (and sculpt at 0.0625), after the
# read-back memory reuse and the per-workload rates. Run in the repo root with .device carried.
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick
O=$OUT/b3/split; mkdir -p $O
export SDFBRICK_RATES=$O/rates.json
for scene in sculpt drops rain; do for cfg in one:0 two:0,1; do
  label=${cfg%%:*} dev=${cfg##*:}
  $B --device $dev --devices split build scenes/$scene.json --brick-size 0.03125 --warmup 1 > /dev/null 2>&1
  $B --device $dev --devices split build scenes/$scene.json --brick-size 0.03125 --warmup 2 --repeat 10 --json $O/build-$scene-$label.json > $O/build-$scene-$label.txt 2>&1
done; done
for cfg in one:0 two:0,1; do label=${cfg%%:*} dev=${cfg##*:}
  $B --device $dev --devices split build scenes/sculpt.json --brick-size 0.0625 --warmup 1 > /dev/null 2>&1
  $B --device $dev --devices split build scenes/sculpt.json --brick-size 0.0625 --warmup 2 --repeat 10 --json $O/build-sculpt0625-$label.json > $O/build-sculpt0625-$label.txt 2>&1
done
