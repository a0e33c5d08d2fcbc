#!/usr/bin/env python3
"""Plot probe histories from a shellflow probes.csv (header: time,<probe names...>).

usage: plot_probes.py OUTDIR/probes.csv [-o probes.png] [--probes NAME ...] [--x COLUMN]
One panel per probe, against time (or against another column with --x, e.g. an amplitude).
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv")
    parser.add_argument("-o", "--output")
    parser.add_argument("--probes", nargs="*", help="plot only these columns")
    parser.add_argument("--x", default="time", help="abscissa column (default: time)")
    parser.add_argument("--x-label", help="axis label of the abscissa (default: 'time [s]' or the column name); "
                                          "a static run's 'time' column is its load factor")
    args = parser.parse_args()
    output = args.output or os.path.splitext(args.csv)[0] + ".png"

    with open(args.csv, newline="") as f:
        rows = list(csv.reader(f))
    if not rows or rows[0][0] != "time":
        print(f"plot_probes: {args.csv}: not a probes file (first column must be 'time')",
              file=sys.stderr)
        return 1
    header, data = rows[0], rows[1:]
    if args.x not in header:
        print(f"plot_probes: no column '{args.x}' in {args.csv}", file=sys.stderr)
        return 1
    names = args.probes or [h for h in header if h not in ("time", args.x)]
    time = [float(r[header.index(args.x)]) for r in data]
    n = max(1, len(names))
    fig, axes = plt.subplots(n, 1, figsize=(8, 2.2 * n + 0.6), sharex=True, squeeze=False)
    for ax, name in zip(axes[:, 0], names):
        if name not in header:
            print(f"plot_probes: no probe '{name}' in {args.csv}", file=sys.stderr)
            return 1
        col = header.index(name)
        ax.plot(time, [float(r[col]) for r in data], "-o" if len(data) < 30 else "-", ms=3)
        ax.set_ylabel(name)
        ax.grid(True, alpha=0.3)
    if not names:
        axes[0, 0].text(0.5, 0.5, "no probes declared", ha="center", transform=axes[0, 0].transAxes)
    axes[-1, 0].set_xlabel(args.x_label or ("time [s]" if args.x == "time" else args.x))
    fig.tight_layout()
    fig.savefig(output, dpi=120)
    print(f"plot_probes: wrote {output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
