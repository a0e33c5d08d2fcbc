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
import math
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


# Up to this many probes: one column of 8 x 2.2 in panels, the probe's name as the y label.
# More: a grid of at most ROWS_MAX rows of smaller panels, the name as the panel's title.
ONE_COLUMN_MAX = 8
ROWS_MAX = 12


def make_axes(n, x_label):
    """A figure with n panels sharing the abscissa, laid out by fixed margins computed from n
    (matplotlib's tight_layout measures every text of every panel: seconds for 48 panels)."""
    ncols = 1 if n <= ONE_COLUMN_MAX else math.ceil(n / ROWS_MAX)
    nrows = math.ceil(n / ncols)
    panel_w, panel_h = (6.9, 1.6) if ncols == 1 else (3.4, 1.45)  # axes size [in]
    gap_w, gap_h = 0.9, (0.6 if ncols == 1 else 0.45)  # room for tick labels, titles [in]
    left, right, top, bottom = 0.9, 0.2, (0.2 if ncols == 1 else 0.45), 0.55
    width = left + right + ncols * panel_w + (ncols - 1) * gap_w
    height = bottom + top + nrows * panel_h + (nrows - 1) * gap_h
    fig = plt.figure(figsize=(width, height))
    fig.subplots_adjust(left=left / width, right=1 - right / width, bottom=bottom / height, top=1 - top / height,
                        wspace=gap_w / panel_w, hspace=gap_h / panel_h)
    grid = fig.add_gridspec(nrows, ncols)
    axes = []
    for k in range(n):
        row, col = k % nrows, k // nrows  # down the columns, in the CSV's order
        # Not sharex: matplotlib then aligns each axis's labels with all its siblings
        # (quadratic in the panels); main() gives every panel the same limits instead.
        ax = fig.add_subplot(grid[row, col])
        last_in_column = row == nrows - 1 or k == n - 1
        if last_in_column:
            ax.set_xlabel(x_label)
        else:
            ax.tick_params(labelbottom=False)
        axes.append(ax)
    return fig, axes


def main(argv=None):
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
    args = parser.parse_args(argv)
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
    fig, axes = make_axes(max(1, len(names)), args.x_label or ("time [s]" if args.x == "time" else args.x))
    for ax, name in zip(axes, names):
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
        if len(axes) > ONE_COLUMN_MAX:
            ax.set_title(name, fontsize=9, y=1.0)  # a fixed y: no search for the tick labels
        else:
            ax.set_ylabel(name)
        if len(axes) > ONE_COLUMN_MAX:
            ax.locator_params(nbins=4)  # matplotlib's ticks are costly objects: fewer of them
        ax.grid(True, alpha=0.3)
    lows = [ax.dataLim.x0 for ax in axes if ax.has_data()]
    highs = [ax.dataLim.x1 for ax in axes if ax.has_data()]
    if lows and max(highs) > min(lows):  # one abscissa range for all, with matplotlib's 5 % margins
        pad = 0.05 * (max(highs) - min(lows))
        for ax in axes:
            ax.set_xlim(min(lows) - pad, max(highs) + pad)
    if not names:
        axes[0].text(0.5, 0.5, "no probes declared", ha="center", transform=axes[0].transAxes)
    fig.savefig(output, dpi=120)
    print(f"plot_probes: wrote {output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
