#!/bin/bash
# The adaptive hard cases generated with seeds the project never used (2 and 3), PoCL here (2 cores):
# render --compare at 480x270, hybrid rays; uniform 0.0625 and adaptive E = 0.008 (finest 0.0625),
# then adaptive E = 0.002 (finest 0.015625). Output: unseen-seeds.txt.
B=build/release/host/sdfbrick
mkdir -p /tmp/aud
for c in ground_trees engraved_slab grooved_board steep_blends; do
  for s in 2 3; do $B scene generate stability/$c --seed $s -o /tmp/aud/$c-$s.json; done
done
for a in "--brick-size 0.0625" "--tolerance 0.008" "--tolerance 0.002"; do
  for c in ground_trees engraved_slab grooved_board steep_blends; do
    for s in 2 3; do
      $B -d cpu render /tmp/aud/$c-$s.json $a --width 480 --height 270 --method hybrid --compare \
        --out /tmp/aud/p.ppm --json /tmp/aud/r.json > /dev/null
      /usr/bin/python3 -c "
import json, sys
r = json.load(open('/tmp/aud/r.json')); a = r['accuracy']
print('$c seed $s $a:', r['bricks'], 'bricks,', 'mismatch %.4f%%' % (100 * a['mismatch_fraction']), 'surfaces p99 %.5f' % a['surface_error_p99_world'], 'depth p99 %.3f vx, %.5f world' % (a['depth_error_p99'], a['depth_error_p99_world']))"
    done
  done
done
