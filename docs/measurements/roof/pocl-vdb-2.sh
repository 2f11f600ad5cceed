#!/bin/bash
# PoCL against the direct OpenVDB fill (bench/vdb_fill) on cubes, whole processes, this machine
# (2 cores), alternating, one uncounted run of each first, then 7 of each: wall and CPU seconds.
export SDFBRICK_DEVICE=cpu
t() { /usr/bin/time -f "%e %U %S" "$@" > /dev/null 2> /tmp/vdb-time.txt; tail -1 /tmp/vdb-time.txt | awk '{printf "wall %s cpu %.2f\n", $1, $2 + $3}'; }
t build/release/host/sdfbrick build scenes/cubes.json -d cpu > /dev/null
t build/release/bench/vdb_fill scenes/cubes.json > /dev/null
for i in 1 2 3 4 5 6 7; do
  echo "$i sdfbrick $(t build/release/host/sdfbrick build scenes/cubes.json -d cpu)"
  echo "$i vdb_fill $(t build/release/bench/vdb_fill scenes/cubes.json)"
done
