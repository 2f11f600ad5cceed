#!/usr/bin/env bash
# Before/after construction of one scene on a GPU and a CPU device, for docs/performance.md.
# usage: bench/construction_ab.sh BEFORE_SDFBRICK AFTER_SDFBRICK OUTDIR [SCENE] [BRICK]
# (defaults: drops, 0.0625). Environment: GPU (default nvidia) and CPU (default cpu) select the
# devices, REPEAT (default 10) the GPU captures, CPU_REPEAT (default 3) the CPU captures.
# Runs the binaries alternately (before, after, before, after) so that drift hits both, and writes
#   OUTDIR/{before,after}-{gpu,cpu}-{1,2}.json   build reports (median device time, stages, digest,
#                                                and the roofline when the binary reports it)
#   OUTDIR/{before,after}-compare.json           render --compare on the GPU (accuracy against the reference)
#   OUTDIR/peaks.txt                             devices --peaks of both devices
#   OUTDIR/summary.md                            times, stages, digests, accuracy and the roofline
#   OUTDIR/roofline.png                          tools/roofline.py's chart of both devices
set -euo pipefail
before=$1 after=$2 out=$3 scene=${4:-drops} brick=${5:-0.0625}
gpu=${GPU:-nvidia} cpu=${CPU:-cpu}
here=$(cd "$(dirname "$0")/.." && pwd)
file="$here/scenes/$scene.json"
mkdir -p "$out"
"$after" -d "$gpu,$cpu" devices --peaks > "$out/peaks.txt"
for round in 1 2; do
  for label in before after; do
    bin=$before; [ "$label" = after ] && bin=$after
    "$bin" -d "$gpu" build "$file" --brick-size "$brick" --repeat "${REPEAT:-10}" --warmup 1 \
      --json "$out/$label-gpu-$round.json" > "$out/$label-gpu-$round.txt"
    "$bin" -d "$cpu" build "$file" --brick-size "$brick" --repeat "${CPU_REPEAT:-3}" --warmup 1 \
      --json "$out/$label-cpu-$round.json" > "$out/$label-cpu-$round.txt"
    echo "construction_ab: round $round $label done" >&2
  done
done
for label in before after; do
  bin=$before; [ "$label" = after ] && bin=$after
  "$bin" -d "$gpu" render "$file" --brick-size "$brick" --width 1920 --height 1080 --compare \
    --out "$out/$label-compare.png" --json "$out/$label-compare.json" > "$out/$label-compare.txt"
done
/usr/bin/python3 - "$out" <<'PY' > "$out/summary.md"
import json, sys, os
out = sys.argv[1]
print("| binary | device | round | median ms | cv % | stages (median ms) | digest | identical |")
print("|---|---|---|---|---|---|---|---|")
for label in ("before", "after"):
    for dev in ("gpu", "cpu"):
        for rnd in (1, 2):
            r = json.load(open(os.path.join(out, f"{label}-{dev}-{rnd}.json")))
            d = r["devices"][0]
            stages = ", ".join(f"{s['name']} {s['median_ms']:.3f}" for s in d["stages"])
            print(f"| {label} | {d['device']['name']} | {rnd} | {d['total_ms']['median_ms']:.3f} | "
                  f"{100 * d['total_ms']['cv']:.2f} | {stages} | {d['digest']} | {d['captures']['identical']} |")
for label in ("before", "after"):
    r = json.load(open(os.path.join(out, f"{label}-compare.json")))
    print(f"\n{label} render --compare: " + json.dumps(r["devices"][0].get("accuracy", r["devices"][0]), sort_keys=True)[:1500])
PY
# The before binary may predate the roofline: its times over the after binary's work (same digests).
/usr/bin/python3 "$here/tools/roofline.py" "before-gpu=$out/before-gpu-2.json@$out/after-gpu-2.json" \
  "after-gpu=$out/after-gpu-2.json" "before-cpu=$out/before-cpu-2.json@$out/after-cpu-2.json" \
  "after-cpu=$out/after-cpu-2.json" --png "$out/roofline.png" >> "$out/summary.md" ||
  echo "construction_ab: no roofline (see above)" >&2
echo "construction_ab: $out/summary.md" >&2
