#!/usr/bin/python3
"""A sculpting session as sdfbrick plays it: a scene with one geometry (a base shape) and an edit log
of strokes on it (docs/frames.md).

usage: /usr/bin/python3 tools/make_sculpt_log.py --scene OUT.json --log OUT.jsonl
           [--strokes 60] [--stroke-edits 8] [--subtract 0.2] [--move 0.1] [--undo 0.1]
           [--base-edits 0] [--seed 1]

The base shape is a sphere of radius 1 (with the strokes' largest blend) and, with --base-edits N, N small blended spheres scattered
over it (a scene already sculpted: --base-edits 65528 gives a 65,536-edit geometry before the log).
Each stroke is --stroke-edits smooth capsules and spheres along a random walk over the surface,
appended in one operation at its own frame; a share of strokes (--subtract) carve instead of add.
After a stroke, with probability --move an edit of an earlier stroke is moved (replace), and with
probability --undo the last stroke is undone (its edits removed, last first, in one frame). The
same seed gives the same files. Prints the operation and frame counts."""
import argparse
import json
import math
import random


def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def rotation_to(d):
    """The unit quaternion [x, y, z, w] that turns +y onto the unit vector d."""
    y = [0.0, 1.0, 0.0]
    dot = max(-1.0, min(1.0, d[1]))
    if dot < -0.999999:
        return [1.0, 0.0, 0.0, 0.0]
    axis = [y[1] * d[2] - y[2] * d[1], y[2] * d[0] - y[0] * d[2], y[0] * d[1] - y[1] * d[0]]
    half = math.acos(dot) / 2.0
    n = math.sqrt(sum(c * c for c in axis)) or 1.0
    q = [c / n * math.sin(half) for c in axis] + [math.cos(half)]
    return [round(c, 12) for c in unit(q)]


def point(v):
    return [round(c, 6) for c in v]


def stroke(rng, edits, subtract):
    """A random walk of edits over the unit sphere's surface."""
    p = unit([rng.gauss(0, 1) for _ in range(3)])
    heading = unit([rng.gauss(0, 1) for _ in range(3)])
    radius = rng.uniform(0.03, 0.08)
    out = []
    for i in range(edits):
        step = [c * rng.uniform(0.05, 0.1) for c in unit([h + rng.gauss(0, 0.4) for h in heading])]
        q = unit([a + b for a, b in zip(p, step)])
        q = [c * rng.uniform(0.98, 1.04) for c in q]
        d = [b - a for a, b in zip(p, q)]
        length = math.sqrt(sum(c * c for c in d))
        mid = [(a + b) / 2 for a, b in zip(p, q)]
        e = {"position": point(mid), "blend": round(rng.uniform(0.02, 0.05), 4)}
        if i % 3 == 2 or length == 0.0:
            e.update({"primitive": "sphere", "radius": round(radius * 1.2, 4)})
        else:
            e.update({"primitive": "capsule", "half_length": round(length / 2, 5), "radius": round(radius, 4),
                      "rotation": rotation_to(unit(d))})
        if subtract:
            e["op"] = "subtract"
        out.append(e)
        heading, p = unit(d) if length else heading, unit(q)
    return out


def base_scene(rng, base_edits):
    # The base sphere carries the strokes' largest blend: the saturation of the band-limited field
    # follows the geometry's largest blend, and a stroke that raised it would change every brick.
    edits = [{"primitive": "sphere", "radius": 1.0, "blend": 0.05}]
    for _ in range(base_edits):
        p = unit([rng.gauss(0, 1) for _ in range(3)])
        edits.append({"primitive": "sphere", "radius": round(rng.uniform(0.02, 0.06), 4),
                      "position": point([c * rng.uniform(0.97, 1.03) for c in p]), "blend": 0.02})
    return {"version": 1, "name": "sculpt-session",
            "camera": {"orbit": {"target": [0, 0, 0], "distance": 4.2, "yaw_deg": 35, "pitch_deg": 20}},
            "geometries": [{"name": "clay", "edits": edits}],
            "objects": [{"geometry": "clay"}]}


def session(rng, args, size):
    """The log's operations; size: the geometry's edit count before the log."""
    ops, strokes, frame = [], [], 0  # strokes: [first index, count] of each stroke still in the list
    for _ in range(args.strokes):
        edits = stroke(rng, args.stroke_edits, rng.random() < args.subtract)
        ops.append({"frame": frame, "op": "append", "geometry": "clay", "edits": edits})
        strokes.append([size, len(edits)])
        size += len(edits)
        frame += 1
        if len(strokes) > 1 and rng.random() < args.move:
            first, count = strokes[rng.randrange(len(strokes) - 1)]
            index = first + rng.randrange(count)
            moved = stroke(rng, 1, False)[0]
            ops.append({"frame": frame, "op": "replace", "geometry": "clay", "index": index, "edit": moved})
            frame += 1
        if strokes and rng.random() < args.undo:
            first, count = strokes.pop()
            for index in reversed(range(first, first + count)):
                ops.append({"frame": frame, "op": "remove", "geometry": "clay", "index": index})
            size -= count
            frame += 1
    return ops, frame


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scene", required=True)
    parser.add_argument("--log", required=True)
    parser.add_argument("--strokes", type=int, default=60)
    parser.add_argument("--stroke-edits", type=int, default=8)
    parser.add_argument("--subtract", type=float, default=0.2)
    parser.add_argument("--move", type=float, default=0.1)
    parser.add_argument("--undo", type=float, default=0.1)
    parser.add_argument("--base-edits", type=int, default=0)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    if args.strokes < 1 or args.stroke_edits < 1 or args.base_edits < 0:
        parser.error("--strokes and --stroke-edits must be >= 1, --base-edits >= 0")
    rng = random.Random(args.seed)
    scene = base_scene(rng, args.base_edits)
    ops, frames = session(rng, args, len(scene["geometries"][0]["edits"]))
    with open(args.scene, "w", encoding="utf-8") as f:
        json.dump(scene, f, separators=(",", ":"))
        f.write("\n")
    with open(args.log, "w", encoding="utf-8") as f:
        for op in ops:
            f.write(json.dumps(op, separators=(",", ":")) + "\n")
    print(f"{args.scene}: {len(scene['geometries'][0]['edits'])} edits; {args.log}: {len(ops)} operations "
          f"over {frames} frames")


if __name__ == "__main__":
    main()
