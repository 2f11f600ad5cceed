#!/usr/bin/python3
"""A PNG chart of a frame loop from `sdfbrick play --json` reports.

usage: /usr/bin/python3 tools/play_chart.py PLAY.json [MORE.json ...] --out CHART.png [--title TEXT]

One panel per report: each frame's device time stacked by stage (construction, BVH, trace, shading)
as bars, its wall time as a line, and the frame budget (1/fps) as a dashed line; the panel's title
gives the device, the placement and the wall percentiles after the first frame. Prints the file
written."""
import argparse
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STAGES = [("construct", "construction", "#4c72b0"), ("bvh", "BVH", "#dd8452"),
          ("trace", "trace", "#55a868"), ("shade", "shading", "#c44e52")]


def load(path):
    try:
        with open(path, encoding="utf-8") as f:
            report = json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"play_chart: {path}: {e}")
    if report.get("command") != "play" or not report.get("frames"):
        sys.exit(f"play_chart: {path}: not a play report with frames")
    return report


def panel(ax, report):
    frames = report["frames"]
    x = [f["frame"] for f in frames]
    bottom = [0.0] * len(frames)
    for key, label, colour in STAGES:
        values = [f["device_ms"][key] for f in frames]
        if any(values):
            ax.bar(x, values, bottom=bottom, width=1.0, color=colour, label=f"device: {label}", linewidth=0)
            bottom = [b + v for b, v in zip(bottom, values)]
    ax.plot(x, [f["wall_ms"] for f in frames], color="black", linewidth=1.0, label="wall")
    s = report["summary"]
    ax.axhline(s["budget_ms"], color="grey", linestyle="--", linewidth=1.0,
               label=f"budget {s['budget_ms']:.2f} ms")
    devices = " + ".join(d["name"] for d in report["devices"])
    w = s["wall_ms"]
    ax.set_title(f"{report['scene']} {report['width']}x{report['height']} {report['method']}, {report['placement']} "
                 f"on {devices}\nframe 0 {s['first_frame_ms']:.1f} ms; after it wall p50 {w['p50']:.2f}, p99 {w['p99']:.2f}, "
                 f"max {w['max']:.2f} ms, {s['over_budget']} of "
                 f"{s['frames'] - s['skipped']} over budget", fontsize=9)
    ax.set_xlabel("frame")
    ax.set_ylabel("ms")
    # The first frame (programs, capacities) would flatten the rest: the axis ends above the others.
    rest = [f["wall_ms"] for f in frames[1:]] or [frames[0]["wall_ms"]]
    ax.set_ylim(0, max(max(rest), s["budget_ms"]) * 1.25)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("reports", nargs="+")
    parser.add_argument("--out", required=True)
    parser.add_argument("--title")
    args = parser.parse_args()
    reports = [load(p) for p in args.reports]
    fig, axes = plt.subplots(len(reports), 1, figsize=(10, 3.2 * len(reports)), squeeze=False)
    for ax, report in zip(axes[:, 0], reports):
        panel(ax, report)
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(args.out)


if __name__ == "__main__":
    main()
