#!/usr/bin/python3
"""PNG charts and a Markdown page from `sdfbrick sweep` CSVs.

usage: /usr/bin/python3 tools/sweep_charts.py SWEEP.csv [MORE.csv ...] --out DIR [--title TEXT]

Several CSVs are concatenated (e.g. one per device). Rows whose status is not "ok" are counted and
listed on the page, never plotted. Writes DIR/*.png and DIR/index.md and prints one line per file.
Empty cells mean unknown; columns this script does not know are ignored, and a chart whose columns
are missing is skipped with a note."""
import argparse
import csv
import os
import re
import shlex
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter, NullLocator  # noqa: E402

REQUIRED = ["scene", "device", "brick_size", "chunk", "cull", "status"]
DEFAULTS = {"chunk": 64, "group": 128, "cull": 1, "format": "int8", "samples": 8,
            "method": "sphere", "normals": "continuous"}
DEFAULT_TEXT = "chunk 64, group 128, cull 1, int8, 8 samples, sphere, continuous normals"
STAGES = ["edit_bounds", "dependencies", "count", "scan", "subdivide", "cull", "check", "order", "evaluate", "aabb"]
OCCUPANCY = ["evaluate_local_bytes", "evaluate_registers", "evaluate_groups_per_cu",
             "evaluate_resident_groups", "evaluate_occupancy"]
MARKERS = "osD^vPX*<>hp"
HOW = {
    "speed": "Each point is one sweep row: further left is faster, lower is more accurate. The step "
             "line per device joins its Pareto front (rows no other row of that device beats in both "
             "time and error); marker shape is the brick size.",
    "stages": "One bar per brick size, stacked from the first construction stage (bottom) to BVH "
              "build and trace (top); the x label says whether the bar is the default-settings row or "
              "the fastest row for that brick size.",
    "bricks": "Log-log construction time against leaf brick count; the fitted exponent b says how "
              "construction scales (b = 1: linear in bricks, b < 1: fixed costs still matter).",
    "adaptive": "Brick-pool memory (left) and construction time (right) against the depth error in geometry "
                "units; solid lines are uniform builds (one point per brick size), dashed ones adaptive builds "
                "(one point per tolerance): the lower curve reaches an accuracy with less.",
    "chunk": "Evaluate-stage time (left axis, one line per brick size, cull=1, median over the other "
             "settings) and evaluate-kernel occupancy (right axis, dashed) against chunk size.",
    "vendors": "The same configuration on every device: one bar per device and brick size, default "
               "settings where swept; a hatched bar had no default-settings row and shows the fastest row.",
}
SECTIONS = {"speed": "Speed against accuracy", "stages": "Stage breakdown",
            "bricks": "Construction time against brick count",
            "adaptive": "Memory and construction time against accuracy",
            "chunk": "Evaluation time and occupancy against chunk size", "vendors": "Vendor comparison"}


def fail(message):
    sys.exit(f"sweep_charts: error: {message}")


def num(row, key):
    """The cell as a float; nan when empty, missing or not a number."""
    try:
        return float(row.get(key) or "nan")
    except ValueError:
        return float("nan")


def finite(values):
    return [v for v in values if np.isfinite(v)]


def median(values):
    values = finite(values)
    return float(np.median(values)) if values else float("nan")


def slug(text):
    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-") or "unnamed"


def group(rows, key):
    """{value: rows} in sorted order of the column's value."""
    out = {}
    for r in rows:
        out.setdefault(r[key], []).append(r)
    return dict(sorted(out.items()))


def total_ms(row):
    t = num(row, "build_ms") + num(row, "trace_ms")
    return t if np.isfinite(t) else np.inf


def is_default(row):
    """True when the row has the default settings; empty cells are not checked."""
    for key, want in DEFAULTS.items():
        cell = (row.get(key) or "").strip().lower()
        if cell and (num(row, key) != want if isinstance(want, int) else cell != want):
            return False
    return True


def one_per_brick(rows):
    """{brick size: (row, rule)}: the default-settings row (fastest if several), else the fastest row."""
    chosen = {}
    for brick, at in group(rows, "_brick").items():
        default = [r for r in at if is_default(r)]
        chosen[brick] = (min(default or at, key=total_ms), "default" if default else "fastest")
    return chosen


def log_axis(ax, axis):
    """Log scale labelled at 1, 2, 5 times powers of ten in plain numbers."""
    (ax.set_xscale if axis == "x" else ax.set_yscale)("log")
    target = ax.xaxis if axis == "x" else ax.yaxis
    target.set_major_locator(LogLocator(subs=(1, 2, 5)))
    target.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    target.set_minor_formatter(NullFormatter())


def autolog(ax, values, axis):
    """Log scale on an axis whose positive values span more than a factor of 20."""
    values = [v for v in finite(values) if v > 0]
    if values and max(values) > 20 * min(values):
        log_axis(ax, axis)


def pareto(points):
    """Points (time, error) not dominated by another point, in order of time."""
    front, best = [], np.inf
    for t, e in sorted(points):
        if e < best:
            front.append((t, e))
            best = e
    return front


class Output:
    """Writes the charts, remembers them for the page, and collects notes about skipped charts."""

    def __init__(self, out, devices, bricks):
        self.out = out
        self.colour = {d: f"C{i % 10}" for i, d in enumerate(devices)}
        self.marker = {b: MARKERS[i % len(MARKERS)] for i, b in enumerate(bricks)}
        self.charts = []  # (kind, caption, file name)
        self.notes = []

    def save(self, fig, kind, name, caption):
        path = os.path.join(self.out, name)
        fig.savefig(path, dpi=110)
        plt.close(fig)
        print(f"wrote {path}")
        self.charts.append((kind, caption, name))

    def note(self, text):
        print(f"note: {text}")
        self.notes.append(text)


def speed_accuracy(out, scene, rows, columns):
    metrics = [(k, label) for k, label in (("depth_p99", "depth error, 99th percentile (voxels)"),
                                           ("normal_mean", "mean normal error (degrees)")) if k in columns]
    if not metrics or not {"build_ms", "trace_ms"} <= columns:
        return out.note(f"speed vs accuracy for {scene} skipped: needs build_ms, trace_ms and depth_p99 or normal_mean")
    fig, axes = plt.subplots(1, len(metrics), figsize=(6 * len(metrics) + 2.5, 5), squeeze=False,
                             constrained_layout=True)
    for ax, (key, label) in zip(axes[0], metrics):
        for device, drows in group(rows, "device").items():
            pts = [(total_ms(r), num(r, key), r["_brick"]) for r in drows]
            pts = [p for p in pts if np.isfinite(p[0]) and np.isfinite(p[1])]
            for brick in sorted({p[2] for p in pts}):
                t, e = zip(*[(p[0], p[1]) for p in pts if p[2] == brick])
                ax.scatter(t, e, color=out.colour[device], marker=out.marker[brick], s=36, alpha=0.75)
            front = pareto([(t, e) for t, e, _ in pts])
            if front:
                ax.step(*zip(*front), where="post", color=out.colour[device], lw=1.5)
        autolog(ax, [total_ms(r) for r in rows], "x")
        ax.set_xlabel("build + trace time (ms)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, which="both")
    handles = ([Line2D([], [], color=c, marker="o", ls="", label=d) for d, c in out.colour.items()
                if any(r["device"] == d for r in rows)]
               + [Line2D([], [], color="grey", marker=m, ls="", label=f"brick {b:g}") for b, m in out.marker.items()
                  if any(r["_brick"] == b for r in rows)]
               + [Line2D([], [], color="black", lw=1.5, label="Pareto front (per device)")])
    axes[0][-1].legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1), fontsize="small")
    fig.suptitle(f"{scene}: speed against accuracy (all ok rows)")
    out.save(fig, "speed", f"speed_accuracy_{slug(scene)}.png", scene)


def memory_vs_accuracy(out, scene, rows, columns):
    """Brick-pool memory and construction time against the depth error in geometry units, uniform
    builds (tolerance 0) beside adaptive ones: which reaches an accuracy with less."""
    if not {"tolerance", "pool_bytes", "build_ms", "depth_p99", "samples"} <= columns:
        return out.note(f"memory vs accuracy for {scene} skipped: needs tolerance, pool_bytes, build_ms, depth_p99")
    if not any(num(r, "tolerance") > 0 for r in rows):
        return out.note(f"memory vs accuracy for {scene} skipped: no adaptive (tolerance > 0) rows")
    fig, axes = plt.subplots(1, 2, figsize=(13, 5), constrained_layout=True)
    for device, drows in group(rows, "device").items():
        for adaptive, marker, style in ((False, "o", "-"), (True, "^", "--")):
            picked = [r for r in drows if (num(r, "tolerance") > 0) == adaptive]
            # depth_p99 is in voxels of the finest brick: brick size / 6 (both layouts have 6 interior voxels)
            pts = sorted((num(r, "depth_p99") * num(r, "brick_size") / 6,
                          num(r, "pool_bytes") / 2**20, num(r, "build_ms")) for r in picked)
            pts = [p for p in pts if all(np.isfinite(v) and v > 0 for v in p)]
            if not pts:
                continue
            label = f"{device}, {'adaptive' if adaptive else 'uniform'}"
            for ax, i in ((axes[0], 1), (axes[1], 2)):
                ax.plot([p[0] for p in pts], [p[i] for p in pts], style, marker=marker, color=out.colour[device],
                        label=label)
    for ax, label in ((axes[0], "brick pool (MiB)"), (axes[1], "construction, median (ms)")):
        log_axis(ax, "x")
        log_axis(ax, "y")
        ax.set_xlabel("depth error, 99th percentile (geometry units)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, which="both")
    axes[1].legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.02, 1))
    fig.suptitle(f"{scene}: memory and construction time against accuracy, uniform and adaptive leaves")
    out.save(fig, "adaptive", f"memory_accuracy_{slug(scene)}.png", scene)


def stage_breakdown(out, scene, device, rows, columns):
    parts = [(f"stage_{s}_ms", s.replace("_", " ")) for s in STAGES if f"stage_{s}_ms" in columns]
    parts += [(k, label) for k, label in (("bvh_ms", "BVH build"), ("trace_ms", "trace")) if k in columns]
    if not parts:
        return out.note(f"stage breakdown for {scene} on {device} skipped: no stage_*_ms, bvh_ms or trace_ms column")
    chosen = one_per_brick(rows)
    bricks = list(chosen)
    x = np.arange(len(bricks))
    bottom = np.zeros(len(bricks))
    fig, ax = plt.subplots(figsize=(8.5, 5), constrained_layout=True)
    cmap = plt.get_cmap("tab20")
    for i, (key, label) in enumerate(parts):
        heights = np.nan_to_num([num(chosen[b][0], key) for b in bricks])
        ax.bar(x, heights, 0.6, bottom=bottom, label=label, color=cmap(i % 20))
        bottom += heights
    ax.set_xticks(x, [f"{b:g}\n({chosen[b][1]})" for b in bricks])
    ax.set_xlabel("leaf brick size (row chosen)")
    ax.set_ylabel("median device time (ms)")
    ax.grid(alpha=0.3, axis="y")
    ax.legend(handles=ax.get_legend_handles_labels()[0][::-1], loc="upper left", bbox_to_anchor=(1.02, 1),
              fontsize="small")
    rules = {rule for _, rule in chosen.values()}
    rule = {frozenset(["default"]): f"default settings\n({DEFAULT_TEXT})",
            frozenset(["fastest"]): "fastest row (min build + trace), no default-settings row"}.get(
        frozenset(rules), f"default settings where present, else fastest row (see x labels)\n({DEFAULT_TEXT})")
    ax.set_title(f"{scene} on {device}: construction stages, BVH and trace\none row per brick size: {rule}",
                 fontsize="medium")
    out.save(fig, "stages", f"stages_{slug(scene)}_{slug(device)}.png", f"{scene} on {device}")


def build_vs_bricks(out, scene, rows, columns):
    if not {"bricks", "build_ms"} <= columns:
        return out.note(f"construction vs brick count for {scene} skipped: needs bricks and build_ms")
    fig, ax = plt.subplots(figsize=(8.5, 5.5), constrained_layout=True)
    fallback = False
    for device, drows in group([r for r in rows if num(r, "cull") == 1], "device").items():
        picked = []
        for at in group(drows, "_brick").values():
            default_chunk = [r for r in at if num(r, "chunk") == DEFAULTS["chunk"]]
            fallback |= not default_chunk
            picked += default_chunk or at
        pts = [(num(r, "bricks"), num(r, "build_ms")) for r in picked]
        pts = np.array([p for p in pts if p[0] > 0 and p[1] > 0])
        if not len(pts):
            continue
        label = device
        if len(set(pts[:, 0])) >= 2:
            b, log_a = np.polyfit(np.log(pts[:, 0]), np.log(pts[:, 1]), 1)
            xs = np.geomspace(pts[:, 0].min(), pts[:, 0].max(), 50)
            ax.plot(xs, np.exp(log_a) * xs ** b, color=out.colour[device], lw=1.2)
            label = f"{device}: build_ms = {np.exp(log_a):.3g} * bricks^{b:.2f}"
        ax.scatter(pts[:, 0], pts[:, 1], color=out.colour[device], s=30, label=label)
    if not ax.collections:
        plt.close(fig)
        return out.note(f"construction vs brick count for {scene} skipped: no cull=1 rows with bricks and build_ms")
    log_axis(ax, "x")
    log_axis(ax, "y")
    ax.set_xlabel("leaf bricks")
    ax.set_ylabel("construction time, median (ms)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize="small")
    rows_used = "cull=1, chunk 64" + (" (all chunks where chunk 64 was not swept)" if fallback else "")
    ax.set_title(f"{scene}: construction time against brick count, power-law fit per device\nrows: {rows_used}",
                 fontsize="medium")
    out.save(fig, "bricks", f"build_vs_bricks_{slug(scene)}.png", scene)


def evaluate_vs_chunk(out, scene, device, rows, columns):
    culled = [r for r in rows if num(r, "cull") == 1 and np.isfinite(r["_chunk"])]
    if "stage_evaluate_ms" not in columns or not culled:
        return out.note(f"evaluate vs chunk for {scene} on {device} skipped: needs stage_evaluate_ms and cull=1 rows")
    chunks = sorted({r["_chunk"] for r in culled})
    fig, ax = plt.subplots(figsize=(8.5, 5), constrained_layout=True)
    for brick, at in group(culled, "_brick").items():
        ys = [median([num(r, "stage_evaluate_ms") for r in at if r["_chunk"] == c]) for c in chunks]
        ax.plot(chunks, ys, marker=out.marker[brick], label=f"evaluate, brick {brick:g}")
    autolog(ax, [num(r, "stage_evaluate_ms") for r in culled], "y")
    ax.set_xscale("log", base=2)
    ax.set_xticks(chunks, [f"{c:g}" for c in chunks])
    ax.xaxis.set_minor_locator(NullLocator())
    ax.set_xlabel("chunk size (log2 axis)")
    ax.set_ylabel("evaluate stage, median (ms)")
    ax.grid(alpha=0.3, which="both")
    handles = ax.get_legend_handles_labels()[0]
    occupancy = [median([num(r, "evaluate_occupancy") for r in culled if r["_chunk"] == c]) for c in chunks]
    if finite(occupancy):
        ax2 = ax.twinx()
        handles += ax2.plot(chunks, np.array(occupancy) * 100, "k--", marker="s", label="occupancy (right axis)")
        ax2.set_ylim(0, 105)
        ax2.set_ylabel("evaluate kernel occupancy (%)")
    else:
        ax.text(0.5, 0.5, f"occupancy unknown on {device}", transform=ax.transAxes, ha="center",
                va="center", fontsize="large", color="dimgrey", bbox=dict(facecolor="white", alpha=0.8, lw=0))
    ax.legend(handles=handles, fontsize="small", loc="upper left",
              bbox_to_anchor=(1.12 if finite(occupancy) else 1.02, 1))
    ax.set_title(f"{scene} on {device}: evaluate time and occupancy against chunk size\n"
                 "rows: cull=1, median over the other settings", fontsize="medium")
    out.save(fig, "chunk", f"evaluate_chunk_{slug(scene)}_{slug(device)}.png", f"{scene} on {device}")


def vendor_comparison(out, scene, rows, columns):
    per_device = {d: one_per_brick(drows) for d, drows in group(rows, "device").items()}
    if len(per_device) < 2:
        return out.note(f"vendor comparison for {scene} skipped: only one device ran it")
    keys = [(k, label) for k, label in (("build_ms", "construction, median (ms)"), ("trace_ms", "trace, median (ms)"))
            if k in columns]
    bricks = sorted({b for chosen in per_device.values() for b in chosen})
    x = np.arange(len(bricks))
    width = 0.8 / len(per_device)
    fig, axes = plt.subplots(1, len(keys), figsize=(6 * len(keys) + 2.5, 5), squeeze=False, constrained_layout=True)
    for ax, (key, label) in zip(axes[0], keys):
        values = []
        for i, (device, chosen) in enumerate(per_device.items()):
            picks = [chosen.get(b, ({}, "none")) for b in bricks]
            heights = [num(row, key) for row, _ in picks]
            values += heights
            bars = ax.bar(x + (i - (len(per_device) - 1) / 2) * width, np.nan_to_num(heights), width,
                          color=out.colour[device], label=device)
            for bar, (_, rule) in zip(bars, picks):
                bar.set_hatch("//" if rule == "fastest" else "")
        autolog(ax, values, "y")
        ax.set_xticks(x, [f"{b:g}" for b in bricks])
        ax.set_xlabel("leaf brick size")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, axis="y", which="both")
    handles = axes[0][-1].get_legend_handles_labels()[0]
    handles.append(Patch(facecolor="white", edgecolor="black", hatch="//", label="fastest row (no default row)"))
    axes[0][-1].legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1), fontsize="small")
    fig.suptitle(f"{scene}: devices compared at the same configuration\n"
                 f"default settings ({DEFAULT_TEXT}) where swept, else fastest row")
    out.save(fig, "vendors", f"vendors_{slug(scene)}.png", scene)


def cell_values(rows, key):
    """Distinct known values of a column as table text ("unknown" when none)."""
    values = sorted(set(finite(num(r, key) for r in rows)))
    if key == "evaluate_occupancy":
        return " / ".join(f"{v * 100:.0f}%" for v in values) or "unknown"
    return " / ".join(f"{v:g}" for v in values) or "unknown"


def occupancy_tables(rows, scenes):
    """Per device: the evaluate kernel's resources per chunk, then waves and evaluate time per scene
    (medians over the cull=1 rows at that chunk with the scene's smallest brick size)."""
    lines = []
    for device, drows in group(rows, "device").items():
        culled = [r for r in drows if num(r, "cull") == 1] or drows
        smallest = {s: min((r["_brick"] for r in culled if r["scene"] == s), default=None) for s in scenes}
        ran = [s for s in scenes if smallest[s] is not None]
        head = ["chunk", "local bytes", "registers", "groups/CU", "resident groups", "occupancy"]
        head += [f"{what}, {s} (brick {smallest[s]:g})" for s in ran for what in ("waves", "evaluate ms")]
        lines += [f"### {device}", "", "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        for chunk, at in group(culled, "_chunk").items():
            cells = [f"{chunk:g}"] + [cell_values(at, k) for k in OCCUPANCY]
            for s in ran:
                sel = [r for r in at if r["scene"] == s and r["_brick"] == smallest[s]]
                for key, form in (("evaluate_waves", "{:.3g}"), ("stage_evaluate_ms", "{:.3f}")):
                    value = median([num(r, key) for r in sel])
                    cells.append(form.format(value) if np.isfinite(value) else "unknown")
            lines.append("| " + " | ".join(cells) + " |")
        lines.append("")
    return lines


def load(paths):
    rows, columns = [], set()
    for path in paths:
        if not os.path.isfile(path):
            fail(f"no such file: {path}")
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            missing = [c for c in REQUIRED if c not in (reader.fieldnames or [])]
            if missing:
                fail(f"{path} lacks the parameter column(s) {', '.join(missing)}: not a `sdfbrick sweep` CSV?")
            columns.update(reader.fieldnames)
            for row in reader:
                row["_file"] = path
                row["_brick"], row["_chunk"] = num(row, "brick_size"), num(row, "chunk")
                rows.append(row)
    ok, failed = [], []
    for r in rows:  # an ok row without a brick size cannot be placed on any chart
        plottable = (r.get("status") or "").strip() == "ok" and np.isfinite(r["_brick"])
        (ok if plottable else failed).append(r)
    return ok, failed, columns


def page(args, out, ok, failed, scenes, devices):
    text = lambda s: str(s or "").replace("|", "\\|").replace("\n", " ")  # noqa: E731
    lines = [f"# {args.title}", "", "Made with:", "", "```", shlex.join([sys.executable] + sys.argv), "```", "",
             f"Inputs: {', '.join(f'`{p}`' for p in args.csv)}: {len(ok)} ok rows, {len(failed)} failed rows; "
             f"scenes: {', '.join(scenes)}; devices: {', '.join(devices)}.", "",
             f"Default settings: {DEFAULT_TEXT}. Times are medians over the repeats of each row.", ""]
    if out.notes:
        lines += ["Skipped:", ""] + [f"- {n}" for n in out.notes] + [""]
    for kind, section in SECTIONS.items():
        charts = [(caption, name) for k, caption, name in out.charts if k == kind]
        if charts:
            lines += [f"## {section}", "", HOW[kind], ""]
            lines += [f"![{caption}]({name})\n" for caption, name in charts]
    lines += ["## Evaluate kernel occupancy", "",
              "Per device and chunk size, from the cull=1 rows; resource values that differ between rows "
              "(e.g. per work-group size) are listed with /. Waves and evaluate ms are medians over the rows "
              "at that chunk with the smallest brick size (most bricks) of each scene.", ""]
    lines += occupancy_tables(ok, scenes)
    lines += [f"## Failed rows ({len(failed)})", ""]
    if failed:
        lines += ["| file | scene | device | brick | chunk | status | error |", "|---|---|---|---|---|---|---|"]
        lines += ["| " + " | ".join(text(r.get(k)) for k in ("_file", "scene", "device", "brick_size", "chunk",
                                                                   "status", "error")) + " |" for r in failed]
    else:
        lines.append("None.")
    path = os.path.join(out.out, "index.md")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"wrote {path}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv", nargs="+", help="CSV written by `sdfbrick sweep`")
    parser.add_argument("--out", required=True, help="directory for the PNGs and index.md")
    parser.add_argument("--title", default="sdfbrick sweep", help="page title")
    args = parser.parse_args()
    ok, failed, columns = load(args.csv)
    if failed:
        print(f"note: {len(failed)} row(s) with status other than ok: listed on the page, not plotted")
    if not ok:
        fail("no rows with status ok")
    os.makedirs(args.out, exist_ok=True)
    scenes, devices = list(group(ok, "scene")), list(group(ok, "device"))
    out = Output(args.out, devices, sorted({r["_brick"] for r in ok}))
    for scene, srows in group(ok, "scene").items():
        speed_accuracy(out, scene, srows, columns)
        for device, drows in group(srows, "device").items():
            stage_breakdown(out, scene, device, drows, columns)
        build_vs_bricks(out, scene, srows, columns)
        memory_vs_accuracy(out, scene, srows, columns)
        for device, drows in group(srows, "device").items():
            evaluate_vs_chunk(out, scene, device, drows, columns)
        if len(devices) >= 2:
            vendor_comparison(out, scene, srows, columns)
    if len(devices) < 2:
        out.note("vendor comparison skipped: the data has only one device")
    page(args, out, ok, failed, scenes, devices)


if __name__ == "__main__":
    main()
