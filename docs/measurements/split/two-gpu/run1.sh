#!/usr/bin/env bash
# Two-GPU split measurements (run in the repo root on nvidia-h200-x2 with .device carried).
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick
O=$OUT/x2; mkdir -p $O
export SDFBRICK_RATES=$O/rates.json SDFBRICK_CACHE_DIR=/tmp/sdfcache
nvidia-smi -L > $O/nvidia-smi.txt 2>&1
$B devices > $O/devices.txt 2>&1
cat $O/devices.txt
run() {  # name, then sdfbrick arguments
    local name=$1; shift
    local t0=$(date +%s.%N)
    "$B" "$@" --json $O/$name.json > $O/$name.txt 2>&1
    echo "$name rc=$? $(echo "$(date +%s.%N) - $t0" | bc) s"
}
# Construction: one GPU vs two, same split code path, 2 warm-ups + 10 captures; each twice
# (seed run stores rates, measured run is balanced by them).
for scene in drops sculpt rain; do
  for brick in 0.03125 0.0625; do
    for cfg in one:0 two:gpu; do
      label=${cfg%%:*} dev=${cfg##*:}
      run seed-build-$scene-$brick-$label --device $dev --devices split build scenes/$scene.json --brick-size $brick --warmup 1
      run build-$scene-$brick-$label --device $dev --devices split build scenes/$scene.json --brick-size $brick --warmup 2 --repeat 10
    done
    run single-build-$scene-$brick --device 0 build scenes/$scene.json --brick-size $brick --warmup 2 --repeat 10
  done
done
# Trace 3840x2160: one GPU vs two.
for scene in drops sculpt; do
  for cfg in one:0 two:gpu; do
    label=${cfg%%:*} dev=${cfg##*:}
    run seed-render-$scene-$label --device $dev --devices split render scenes/$scene.json --width 3840 --height 2160 --warmup 1 --out /tmp/$scene-$label-seed.ppm
    run render-$scene-$label --device $dev --devices split render scenes/$scene.json --width 3840 --height 2160 --warmup 2 --repeat 10 --out /tmp/$scene-$label.ppm
  done
  cmp /tmp/$scene-one.ppm /tmp/$scene-two.ppm && echo "$scene 4K images identical" | tee $O/cmp-$scene.txt
  run single-render-$scene --device 0 render scenes/$scene.json --width 3840 --height 2160 --warmup 2 --repeat 10 --out /tmp/$scene-single.ppm
  cmp /tmp/$scene-one.ppm /tmp/$scene-single.ppm && echo "$scene split-one and plain images identical" | tee -a $O/cmp-$scene.txt
done
# Faults on GPU 1 mid-job (launch failures at several points, an allocation failure).
for f in launch@1:5 launch@1:40 launch@1:200 alloc@1:3; do
  SDFBRICK_FAULT=$f run fault-build-drops-$f --device gpu --devices split build scenes/drops.json --brick-size 0.03125
  SDFBRICK_FAULT=$f run fault-render-drops-$f --device gpu --devices split render scenes/drops.json --width 3840 --height 2160 --out /tmp/fault.ppm
  cmp /tmp/fault.ppm /tmp/drops-one.ppm && echo "fault $f: image identical" | tee -a $O/cmp-fault.txt
done
cd $OUT && tar czf x2.tgz x2 && rm -rf x2
