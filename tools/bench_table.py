#!/usr/bin/python3
"""Markdown table of a bench_build or bench_trace Google Benchmark JSON.
bench_build: time per scene and brick size, culling on/off.
bench_trace: BVH build and trace time per scene and brick size (3840 x 2160).
usage: tools/bench_table.py BENCH.json"""
import json
import sys

data = json.load(open(sys.argv[1]))
rows = {}
for b in data["benchmarks"]:
    kind, scene, leaf = b["name"].split("/")[:3]
    mode = b["name"].split("/")[3] if kind == "build" else kind
    rows.setdefault((scene, float(leaf)), {})[mode] = b
ctx = data["context"]
print(f"device: {ctx.get('device')} ({ctx.get('platform')}, driver {ctx.get('driver')})\n")
order = sorted(rows.items(), key=lambda kv: (kv[0][0], -kv[0][1]))
if any("cull" in m for _, m in order):
    print("| scene | brick | leaf bricks | edits/leaf | cull: ms | evaluate ms | Mbricks/s | G edit evals/s | no cull: ms |")
    print("|---|---|---|---|---|---|---|---|---|")
    for (scene, leaf), m in order:
        c, n = m.get("cull"), m.get("nocull")
        if c is None:
            continue
        nocull = f"{n['real_time']:.3f}" if n else "not run"
        print(f"| {scene} | {leaf} | {int(c['bricks'])} | {c['edits/leaf']:.2f} | {c['real_time']:.3f} | "
              f"{c.get('evaluate_ms', 0):.3f} | {c['bricks/s'] / 1e6:.2f} | {c['edit_evals/s'] / 1e9:.1f} | {nocull} |")
else:
    label = next((b.get("label", "") for b in data["benchmarks"] if b["name"].startswith("trace/")), "")
    print(f"trace: {label}\n")
    print("| scene | brick | leaf bricks | BVH ms | trace ms | G rays/s | node visits/ray | brick steps/ray |")
    print("|---|---|---|---|---|---|---|---|")
    for (scene, leaf), m in order:
        b, t = m.get("bvh"), m.get("trace")
        if t is None:
            continue
        bvh = f"{b['real_time']:.3f}" if b else "not run"
        print(f"| {scene} | {leaf} | {int(t['bricks'])} | {bvh} | {t['real_time']:.3f} | {t['rays/s'] / 1e9:.3f} | "
              f"{t['visits/ray']:.1f} | {t['steps/ray']:.1f} |")
