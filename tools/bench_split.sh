#!/usr/bin/env bash
# Split-mode timings (docs/multi-device.md, "Measured"): for each scene and device configuration,
# `build` and `render` with --devices split and one warm-up pass, each run twice (the first run
# stores the devices' measured rates, the second is balanced by them and reported), then a table of the construction and trace wall times, the shares and
# the speed-up against the first configuration. A configuration of one device runs the same code
# path on that device alone.
#
#   tools/bench_split.sh SDFBRICK OUTDIR "LABEL|ENV|DEVICES" ...
#
# ENV is a space-separated list of VAR=value (may be empty), DEVICES a --device spec. Example:
#   tools/bench_split.sh build/release/host/sdfbrick /tmp/split \
#     "1 device, 1 core|POCL_DEVICES=pthread POCL_MAX_PTHREAD_COUNT=1 POCL_CPU_MAX_CU_NUM=1|0" \
#     "2 devices, 1 core each|POCL_DEVICES='pthread pthread' POCL_MAX_PTHREAD_COUNT=1 POCL_CPU_MAX_CU_NUM=1|cpu"
# SCENES (default "drops rain"), BRICK (0.125), WIDTH/HEIGHT (1280x720) may be set in the environment.
set -euo pipefail
(($# >= 3)) || { echo "usage: tools/bench_split.sh SDFBRICK OUTDIR \"LABEL|ENV|DEVICES\"..." >&2; exit 2; }
bin=$(realpath "$1") out=$2
shift 2
cd "$(dirname "$0")/.."
mkdir -p "$out"
scenes=${SCENES:-drops rain} brick=${BRICK:-0.125} width=${WIDTH:-1280} height=${HEIGHT:-720}
n=0
for config in "$@"; do
    IFS='|' read -r label envs devices <<< "$config"
    echo "$label" > "$out/config-$n.label"
    for scene in $scenes; do
        for verb in build render; do
            extra=""
            [[ $verb == render ]] && extra="--width $width --height $height --out $out/$scene-$n.ppm"
            for round in seed measured; do  # the first run stores the rates that balance the second
                eval "env $envs SDFBRICK_RATES=$out/rates-$scene-$n.json" "$bin" --device "$devices" --devices split \
                    $verb "scenes/$scene.json" --brick-size "$brick" --warmup 1 $extra \
                    --json "$out/$verb-$scene-$n.json" > /dev/null
            done
        done
    done
    n=$((n + 1))
done
/usr/bin/python3 - "$out" "$n" "$scenes" << 'EOF'
import json, sys
out, n, scenes = sys.argv[1], int(sys.argv[2]), sys.argv[3].split()
print("| scene | configuration | construction ms | speed-up | trace ms | speed-up | shares (construct / trace) |")
print("|---|---|---|---|---|---|---|")
for scene in scenes:
    base = None
    for i in range(n):
        label = open(f"{out}/config-{i}.label").read().strip()
        b = json.load(open(f"{out}/build-{scene}-{i}.json"))
        r = json.load(open(f"{out}/render-{scene}-{i}.json"))
        c, t = b["placement"]["construct"]["wall_ms"], r["placement"]["trace"]["wall_ms"]
        base = base or (c, t)
        shares = " / ".join(
            ", ".join(f"{100 * d['done']:.0f}%" for d in s["devices"]) for s in (b["placement"]["construct"], r["placement"]["trace"]))
        print(f"| {scene} | {label} | {c:.0f} | {base[0] / c:.2f}x | {t:.0f} | {base[1] / t:.2f}x | {shares} |")
        if b["bricks"] != r["bricks"]:
            sys.exit(f"{scene}: build and render brick counts differ")
    digests = {json.load(open(f"{out}/render-{scene}-{i}.json"))["digest"] for i in range(n)}
    print(f"\n{scene}: image digests of all configurations equal: {len(digests) == 1}\n")
EOF
