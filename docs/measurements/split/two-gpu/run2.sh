#!/usr/bin/env bash
set -uo pipefail
source .device/env.sh
B=$PWD/.device/bin/sdfbrick
O=$OUT/x2b; mkdir -p $O
export SDFBRICK_RATES=$O/rates.json SDFBRICK_CACHE_DIR=/tmp/sdfcache
run() { local name=$1; shift; "$B" "$@" --json $O/$name.json > $O/$name.txt 2>&1; echo "$name rc=$?"; }
for scene in drops rain sculpt; do
  for cfg in one:0 two:gpu; do
    label=${cfg%%:*} dev=${cfg##*:}
    run seed-build-$scene-$label --device $dev --devices split build scenes/$scene.json --brick-size 0.03125 --warmup 1
    run build-$scene-$label --device $dev --devices split build scenes/$scene.json --brick-size 0.03125 --warmup 2 --repeat 10
  done
done
for cfg in one:0 two:gpu; do
  label=${cfg%%:*} dev=${cfg##*:}
  run seed-render-drops-$label --device $dev --devices split render scenes/drops.json --width 3840 --height 2160 --warmup 1 --out /tmp/d-$label.ppm
  run render-drops-$label --device $dev --devices split render scenes/drops.json --width 3840 --height 2160 --warmup 2 --repeat 10 --out /tmp/d-$label.ppm
done
cmp /tmp/d-one.ppm /tmp/d-two.ppm && echo "drops 4K identical" | tee $O/cmp.txt
for f in $O/build-*.txt $O/render-*.txt; do echo "== $f"; grep -v "^report\|^picture" $f; done
cd $OUT && tar czf x2b.tgz x2b && rm -rf x2b
