#!/usr/bin/python3
"""Roofline of construction stages from `sdfbrick build --json` reports.

usage: tools/roofline.py LABEL=REPORT.json[@WORK.json] ... [--png chart.png] [--title TEXT]
Each report's "roofline" (per device: count, cull and evaluate with their FP32 FLOPs, compulsory
global-memory bytes and median device time, and the device's cached `devices --peaks`) becomes a
markdown table row per device and stage: ms, GFLOP/s and its share of the FMA peak, GB/s and its
share of the bandwidth peak, FLOP per byte. With --png, one chart per device name: the stages as
points (FLOP/byte, GFLOP/s), one marker per label, under the roofs min(FMA peak, bandwidth x FLOP/byte).
REPORT@WORK takes the stage times from REPORT and the work and peaks from WORK, a report of the same
build (equal digests) by a binary that counts the work: a build from before the roofline existed
does the same work when its digest is the same.
"""
import argparse
import json
import sys


def read(path):
    try:
        return json.load(open(path))
    except (OSError, ValueError) as error:
        sys.exit(f"roofline: {path}: {error}")


def load(pairs):
    rows = []
    for pair in pairs:
        label, sep, paths = pair.partition("=")
        if not sep:
            sys.exit(f"roofline: expected LABEL=REPORT.json, got {pair!r}")
        path, _, work_path = paths.partition("@")
        report = read(path)
        work = read(work_path) if work_path else report
        for device, counted in zip(report.get("devices", []), work.get("devices", [])):
            roofline = counted.get("roofline")
            if roofline is None:
                sys.exit(f"roofline: {work_path or path}: no roofline (use REPORT@WORK with a newer binary's report)")
            if device["digest"] != counted["digest"]:
                sys.exit(f"roofline: {path} and {work_path}: different digests, not the same work")
            times = {s["name"]: s["median_ms"] for s in device["stages"]}
            for stage in roofline["stages"]:
                ms = times.get(stage["stage"], 0.0)
                row = {"label": label, "device": device["device"]["name"], "peaks": roofline["peaks"], **stage, "ms": ms}
                row["gflops"] = stage["flop"] / (ms * 1e6) if ms > 0 else 0.0
                row["gbps"] = stage["bytes"] / (ms * 1e6) if ms > 0 else 0.0
                rows.append(row)
    return rows


def share(value, peak):
    return f"{100.0 * value / peak:.2f}%" if peak else "-"


def table(rows):
    print("| label | device | stage | ms | GFLOP/s | of FMA peak | GB/s | of bandwidth | FLOP/byte |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        peaks = r["peaks"] or {}
        print(f"| {r['label']} | {r['device']} | {r['stage']} | {r['ms']:.3f} | {r['gflops']:.3f} | "
              f"{share(r['gflops'], peaks.get('fma_gflops'))} | {r['gbps']:.3f} | "
              f"{share(r['gbps'], peaks.get('bandwidth_gbps'))} | {r['flop_per_byte']:.2f} |")


def chart(rows, png, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    devices = sorted({r["device"] for r in rows})
    fig, axes = plt.subplots(1, len(devices), figsize=(6.5 * len(devices), 5), squeeze=False)
    markers = "osD^v*"
    labels = list(dict.fromkeys(r["label"] for r in rows))
    stages = list(dict.fromkeys(r["stage"] for r in rows))
    for ax, device in zip(axes[0], devices):
        mine = [r for r in rows if r["device"] == device and r["ms"] > 0]
        peaks = next((r["peaks"] for r in mine if r["peaks"]), None)
        xs = [r["flop_per_byte"] for r in mine if r["flop_per_byte"] > 0]
        lo, hi = min(xs + [0.1]) / 4, max(xs + [100.0]) * 4
        if peaks:
            bw, fma = peaks["bandwidth_gbps"], peaks["fma_gflops"]
            grid = [lo * (hi / lo) ** (i / 200) for i in range(201)]
            ax.plot(grid, [min(fma, bw * x) for x in grid], "k-", lw=1.2,
                    label=f"peaks: {fma:.1f} GFLOP/s FMA, {bw:.1f} GB/s")
            ax.plot(grid, [min(fma / 2, bw * x) for x in grid], "k--", lw=0.8, label="half the FMA peak (no FMA to fuse)")
        for r in mine:
            colour = f"C{stages.index(r['stage'])}"
            ax.plot(r["flop_per_byte"], r["gflops"], markers[labels.index(r["label"]) % len(markers)], color=colour,
                    ms=8, label=f"{r['label']}: {r['stage']}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("FP32 FLOP per compulsory byte")
        ax.set_ylabel("achieved GFLOP/s")
        ax.set_title(device if not title else f"{title}\n{device}", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("reports", nargs="+", help="LABEL=REPORT.json")
    parser.add_argument("--png", help="write the chart here")
    parser.add_argument("--title", default="", help="chart title")
    args = parser.parse_args()
    rows = load(args.reports)
    table(rows)
    if args.png:
        chart(rows, args.png, args.title)


if __name__ == "__main__":
    main()
