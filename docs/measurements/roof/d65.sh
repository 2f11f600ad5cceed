#!/bin/bash
# d65: one binary (this commit's host with two temporary knobs, not kept: EXP_WRITE_SPAN and
# EXP_MARK_SPAN cap cull_write's and cull_mark's bits per work-item on GPUs), kernels loaded with
# --kernel-dir: kz (77b5149's) and kc (kz with the running value saturated on one side after an
# add or a subtract, sdf_saturate) and kd (kc whose one-lane evaluation reads each edit from global
# memory, no staging). Variants alternating, two rounds of 10 captures.
source .device/env.sh
export SDFBRICK_CACHE_DIR=/tmp/sdfcache
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
X="--warmup 1 --repeat 10"
S=scenes/stability
B=.device/bin/sdfbrick-exp
ev() { grep -oE 'count [0-9.]+|cull [0-9.]+|check [0-9.]+|evaluate [0-9.]+|total [0-9.]+ ms|wall [0-9.]+|^  digest [0-9a-f]+.*' | head -10 | tr '\n' ' '; }
$B scene generate sculpt_dense -o /tmp/sculpt_dense.json > /dev/null 2>&1
run() { # name env kernels config
  echo "$1 $4: $(env $2 timeout 40 $B -d gpu --kernel-dir .device/$3 build $4 $X 2>&1 | ev)"; }
for r in 1 2; do
  for c in "scenes/drops.json --brick-size 0.0625" "scenes/rubble.json --brick-size 0.0625" "/tmp/sculpt_dense.json --brick-size 0.0625" \
           "scenes/sculpt.json --brick-size 0.0625" "scenes/rain.json --brick-size 0.0625" "scenes/board.json --brick-size 0.03125" \
           "$S/edits_65536.json --brick-size 0.0625" "$S/ground_trees.json --brick-size 0.0625" \
           "$S/engraved_slab.json --brick-size 0.0625 --tolerance 0.008" "scenes/drops.json --brick-size 0.03125 --tolerance 0.001"; do
    run "$r base" "X=0" kz "$c"
    run "$r W1" "EXP_WRITE_SPAN=1" kz "$c"
    run "$r W4" "EXP_WRITE_SPAN=4" kz "$c"
    run "$r W8" "EXP_WRITE_SPAN=8" kz "$c"
    run "$r M4" "EXP_MARK_SPAN=4" kz "$c"
    run "$r kc" "X=0" kc "$c"
    run "$r kd" "X=0" kd "$c"
  done
done
for d in gpu cpu; do for sc in scenes/drops.json scenes/rubble.json scenes/rain.json scenes/board.json; do
  echo "gpu kd $sc 0.125: $(timeout 60 $B -d gpu --kernel-dir .device/kd build $sc --brick-size 0.125 2>&1 | grep -oE 'digest [0-9a-f]+.*')"
  echo "$d kc $sc 0.125: $(timeout 60 $B -d $d --kernel-dir .device/kc build $sc --brick-size 0.125 2>&1 | grep -oE 'digest [0-9a-f]+.*')"; done; done
for v in "X=0" "EXP_WRITE_SPAN=1" "EXP_WRITE_SPAN=8"; do
  echo "== $v kc drops 0.0625 kernel stats"; env $v timeout 40 $B -d gpu --kernel-dir .device/kc build scenes/drops.json --brick-size 0.0625 $X --kernel-stats 2>&1 | grep -E "stages|^  [a-z_]+ +[a-z,]+ +[0-9]+ |^    level|digest"
done
echo "== peaks and drops' roofline (kc)"
timeout 120 $B -d gpu devices --peaks 2>&1 | tail -8
timeout 60 $B -d gpu --kernel-dir .device/kc build scenes/drops.json --brick-size 0.0625 $X 2>&1 | grep -A6 "roofline"
