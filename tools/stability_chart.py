#!/usr/bin/python3
"""The stability atlas's table and chart from `sdfbrick stability --json` reports.

usage: tools/stability_chart.py REPORT.json [REPORT.json ...] [--png chart.png] [--title TEXT]
                                [--pictures DIR --strips OUTDIR]
Several reports (e.g. one run per method) are joined cell by cell. Prints a markdown table, cases down and in-brick methods across, each cell the failure rate of that
method on that case over the report's cells (normal rules x formats x builds) with the measures that
failed and how often; with --png, draws the same rates as grouped bars (matplotlib). With --pictures
(the folder `sdfbrick stability --pictures` wrote) and --strips, writes OUTDIR/CASE.png per case: the
reference and each method's render on top, each method's difference image below.
"""
import argparse
import collections
import json
import sys


def load(path):
    try:
        report = json.load(open(path))
    except (OSError, ValueError) as error:
        sys.exit(f"stability_chart: {path}: {error}")
    if report.get("command") != "stability":
        sys.exit(f"stability_chart: {path}: not a stability report")
    return report


def rates(cells):
    """{case: {method: (failed, total, Counter of failures)}}, cases and methods in report order."""
    table = collections.OrderedDict()
    for cell in cells:
        row = table.setdefault(cell["case"], collections.OrderedDict())
        failed, total, why = row.get(cell["method"], (0, 0, collections.Counter()))
        why.update(cell["failures"])
        row[cell["method"]] = (failed + bool(cell["failed"]), total + 1, why)
    return table


def methods_of(table):
    seen = []
    for row in table.values():
        seen += [m for m in row if m not in seen]
    return seen


def markdown(table):
    methods = methods_of(table)
    lines = ["| case | " + " | ".join(methods) + " |", "|---" * (len(methods) + 1) + "|"]
    for case, row in table.items():
        cells = []
        for m in methods:
            if m not in row:
                cells.append("")
                continue
            failed, total, why = row[m]
            text = f"{100.0 * failed / total:.0f}% ({failed}/{total})"
            if why:
                text += ": " + ", ".join(f"{k} {v}" for k, v in sorted(why.items()))
            cells.append(text)
        lines.append(f"| {case} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def chart(table, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    methods = methods_of(table)
    cases = list(table)
    width = 0.8 / max(len(methods), 1)
    fig, ax = plt.subplots(figsize=(max(8, 0.7 * len(cases)), 4.5))
    for i, m in enumerate(methods):
        ys = [100.0 * table[c][m][0] / table[c][m][1] if m in table[c] else 0.0 for c in cases]
        ax.bar([x + (i - (len(methods) - 1) / 2) * width for x in range(len(cases))], ys, width, label=m)
    ax.set_xticks(range(len(cases)))
    ax.set_xticklabels(cases, rotation=40, ha="right")
    ax.set_ylabel("failing cells (%)")
    ax.set_ylim(0, 105)
    ax.set_title(title)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def strips(table, pictures, outdir):
    import os
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as mpimg
    import matplotlib.pyplot as plt
    os.makedirs(outdir, exist_ok=True)
    methods = methods_of(table)
    for case in table:
        fig, axes = plt.subplots(2, len(methods) + 1, figsize=(3.2 * (len(methods) + 1), 4.0), squeeze=False)
        panels = [(0, 0, f"{case}-reference", "reference")] + \
                 [(0, i + 1, f"{case}-{m}", m) for i, m in enumerate(methods)] + \
                 [(1, i + 1, f"{case}-{m}-difference", f"{m}: difference") for i, m in enumerate(methods)]
        for ax in axes.flat:
            ax.axis("off")
        for row, col, name, title in panels:
            path = os.path.join(pictures, name + ".png")
            if os.path.exists(path):
                axes[row][col].imshow(mpimg.imread(path))
                axes[row][col].set_title(title, fontsize=9)
        fig.suptitle(case, fontsize=10)
        fig.tight_layout()
        fig.savefig(os.path.join(outdir, case + ".png"), dpi=80)
        plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("reports", nargs="+")
    parser.add_argument("--png")
    parser.add_argument("--title", default="stability atlas: failing cells per case and method")
    parser.add_argument("--pictures")
    parser.add_argument("--strips")
    args = parser.parse_args()
    cells = [cell for path in args.reports for cell in load(path)["cells"]]
    table = rates(cells)
    print(markdown(table))
    if args.png:
        chart(table, args.png, args.title)
    if args.pictures and args.strips:
        strips(table, args.pictures, args.strips)


if __name__ == "__main__":
    main()
