#!/usr/bin/python3
"""Markdown table of a bench_build Google Benchmark JSON: time per scene and brick size, culling on/off.
usage: tools/bench_table.py BENCH.json"""
import json
import sys

data = json.load(open(sys.argv[1]))
rows = {}
for b in data["benchmarks"]:
    _, scene, leaf, mode = b["name"].split("/")[:4]
    rows.setdefault((scene, float(leaf)), {})[mode] = b
ctx = data["context"]
print(f"device: {ctx.get('device')} ({ctx.get('platform')}, driver {ctx.get('driver')})\n")
print("| scene | brick | leaf bricks | edits/leaf | cull: ms | evaluate ms | Mbricks/s | G edit evals/s | no cull: ms |")
print("|---|---|---|---|---|---|---|---|---|")
for (scene, leaf), m in sorted(rows.items(), key=lambda kv: (kv[0][0], -kv[0][1])):
    c, n = m.get("cull"), m.get("nocull")
    if c is None:
        continue
    nocull = f"{n['real_time']:.3f}" if n else "not run"
    print(f"| {scene} | {leaf} | {int(c['bricks'])} | {c['edits/leaf']:.2f} | {c['real_time']:.3f} | "
          f"{c.get('evaluate_ms', 0):.3f} | {c['bricks/s'] / 1e6:.2f} | {c['edit_evals/s'] / 1e9:.1f} | {nocull} |")
