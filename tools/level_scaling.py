#!/usr/bin/python3
"""Power-law fit of construction time against brick count (bench/level_scaling.sh's JSON reports).

usage: tools/level_scaling.py DIR [--png chart.png] [--label TEXT]
Fits device time = a * bricks^b per scene over every leaf size found (least squares in log-log) and
prints a markdown table: leaf size, leaf bricks, bricks of all levels, median device ms, and the
exponent b. A construction whose cost follows the surface has b close to 1; a level kept dense would
make it grow with the volume instead.
"""
import argparse
import glob
import json
import math
import os
import sys


def load(directory):
    rows = {}
    for path in sorted(glob.glob(os.path.join(directory, "*.json"))):
        name = os.path.basename(path)[:-5]
        scene, _, leaf = name.rpartition("-")
        try:
            report = json.load(open(path))
            leaf_size = float(leaf)
        except (ValueError, OSError) as error:
            sys.exit(f"level_scaling: {path}: {error}")
        geometry = report["devices"][0]["geometries"][0]
        rows.setdefault(scene, []).append({
            "leaf": leaf_size,
            "bricks": report["bricks"],
            "all_levels": sum(level["bricks"] for level in geometry["levels"]),
            "ms": report["devices"][0]["total_ms"]["median_ms"],
            "device": report["devices"][0]["device"]["name"],
        })
    return rows


def fit(points):
    xs = [math.log(p["bricks"]) for p in points]
    ys = [math.log(p["ms"]) for p in points]
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else float("nan")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("dir")
    parser.add_argument("--png")
    parser.add_argument("--label", default="")
    args = parser.parse_args()
    rows = load(args.dir)
    if not rows:
        sys.exit(f"level_scaling: no reports in {args.dir}")
    for scene, points in sorted(rows.items()):
        points.sort(key=lambda p: -p["leaf"])
        print(f"{scene} on {points[0]['device']}: exponent {fit(points):.3f}")
        print("| leaf | leaf bricks | bricks, all levels | device ms (median) |")
        print("| --- | --- | --- | --- |")
        for p in points:
            print(f"| {p['leaf']} | {p['bricks']:,} | {p['all_levels']:,} | {p['ms']:.3f} |")
        print()
    if args.png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 4))
        for scene, points in sorted(rows.items()):
            ax.loglog([p["bricks"] for p in points], [p["ms"] for p in points], "o-",
                      label=f"{scene} (exponent {fit(points):.2f})")
        ax.set_xlabel("leaf bricks")
        ax.set_ylabel("construction, device ms (median)")
        ax.set_title(f"Construction time against bricks {args.label}".strip())
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(args.png, dpi=120)


if __name__ == "__main__":
    main()
