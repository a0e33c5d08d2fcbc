#!/usr/bin/env python3
"""Plot probe histories from a shellflow probes.csv (header: time,<probe names...>).

usage: plot_probes.py OUTDIR/probes.csv [-o probes.png] [--probes NAME ...] [--x COLUMN]
                      [--x-label TEXT] [--reference PROBE FILE COLUMN SCALE LABEL ...]
One panel per probe, against time (or against another column with --x, e.g. an amplitude).
--reference draws SCALE times column COLUMN of the CSV FILE (its first column the abscissa,
lines starting with # are comments) in PROBE's panel, as `shellflow run` does for a probe's
`reference:` key (docs/case-format.md).
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_reference(path, column, scale):
    """(abscissa, SCALE * column) of a reference CSV, or None after a message."""
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].lstrip().startswith("#")]
    header = [h.strip() for h in rows[0]] if rows else []
    if column not in header[1:]:
        print(f"plot_probes: no column '{column}' in {path}", file=sys.stderr)
        return None
    col = header.index(column)
    return [float(r[0]) for r in rows[1:]], [scale * float(r[col]) for r in rows[1:]]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv")
    parser.add_argument("-o", "--output")
    parser.add_argument("--probes", nargs="*", help="plot only these columns")
    parser.add_argument("--x", default="time", help="abscissa column (default: time)")
    parser.add_argument("--x-label", help="axis label of the abscissa (default: 'time [s]' or the column name); "
                                          "a static run's 'time' column is its load factor")
    parser.add_argument("--reference", nargs=5, action="append", default=[],
                        metavar=("PROBE", "FILE", "COLUMN", "SCALE", "LABEL"),
                        help="draw SCALE * COLUMN of FILE (first column: the abscissa) beside PROBE")
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
        ax.plot(time, [float(r[col]) for r in data], "-o" if len(data) < 30 else "-", ms=3,
                label="shellflow")
        references = [r for r in args.reference if r[0] == name]
        for _, path, column, scale, label in references:
            curve = read_reference(path, column, float(scale))
            if curve is None:
                return 1
            ax.plot(curve[0], curve[1], "k--", lw=1.2, label=label)
            print(f"plot_probes: {name}: reference {scale} x {os.path.basename(path)}:{column} "
                  f"({len(curve[0])} points)")
        if references:
            ax.legend(fontsize=8)
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
