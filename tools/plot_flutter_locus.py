#!/usr/bin/env python3
"""Plots of a linear flutter analysis (shellflow flutter): frequency against the parameter
(the V-f plot of NASTRAN SOL 145), damping g = 2 sigma / omega against the parameter (V-g),
and the root locus (growth rate against frequency, coloured by the parameter), with the
critical point of flutter.json marked.

usage: plot_flutter_locus.py OUTDIR/flutter_locus.csv [--summary OUTDIR/flutter.json]
                             [-o OUTDIR/flutter_locus.png] [--roots N]
"""
import argparse
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(text):
    return float(text) if text not in ("", "null", "nan") else math.nan


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--summary", help="flutter.json (critical point, parameter name)")
    ap.add_argument("-o", "--output", help="PNG (default: flutter_locus.png next to the CSV)")
    ap.add_argument("--roots", type=int, default=6, help="lowest roots plotted (default 6)")
    args = ap.parse_args(argv)

    summary = {}
    if args.summary and os.path.exists(args.summary):
        with open(args.summary) as f:
            summary = json.load(f)
    parameter = summary.get("parameter", "lambda")
    roots = {}
    with open(args.csv, newline="") as f:
        for row in csv.DictReader(f):
            k = int(row["root"])
            if k > args.roots:
                continue
            r = roots.setdefault(k, {"x": [], "f": [], "g": [], "sigma": []})
            r["x"].append(number(row["value"]))
            r["f"].append(number(row["frequency_hz"]))
            r["g"].append(number(row["damping_g"]))
            r["sigma"].append(number(row["growth_rate"]))
    if not roots:
        sys.exit(f"plot_flutter_locus: {args.csv} has no roots")

    label = r"$\lambda = \rho U^2 a^3 / (\beta D)$" if parameter == "lambda" else "Mach number"
    fig, (ax_f, ax_g, ax_l) = plt.subplots(1, 3, figsize=(15, 4.6))
    for k in sorted(roots):
        r = roots[k]
        ax_f.plot(r["x"], r["f"], "-", lw=1.3, label=f"root {k}")
        ax_g.plot(r["x"], r["g"], "-", lw=1.3)
        sc = ax_l.scatter(r["f"], r["sigma"], c=r["x"], s=6, cmap="viridis")
    fig.colorbar(sc, ax=ax_l, label=label)
    ax_g.axhline(0.0, color="k", lw=0.8)
    ax_l.axhline(0.0, color="k", lw=0.8)
    crit = summary.get("critical_value")
    title = summary.get("case", "")
    if crit is not None:
        for ax in (ax_f, ax_g):
            ax.axvline(crit, color="r", ls="--", lw=1.0)
        ax_l.plot([summary["frequency_hz"]], [0.0], "r*", ms=12)
        title += (f": $\\lambda_{{cr}}$ = {summary['lambda_cr']:.5g}, "
                  + (f"$M_{{cr}}$ = {summary['mach_cr']:.5g}, " if summary.get("mach_cr") is not None else "")
                  + f"{summary['frequency_hz']:.5g} Hz")
    else:
        title += ": no flutter boundary in the range"
    if summary:
        title += " (" + (f"{summary['modes']} modes" if summary.get("modes") else "full system") + (
            ", aerodynamic damping)" if summary.get("aerodynamic_damping") else ", no aerodynamic damping)")
    ax_f.set_xlabel(label)
    ax_f.set_ylabel("frequency [Hz]")
    ax_f.legend(fontsize=8)
    ax_g.set_xlabel(label)
    ax_g.set_ylabel(r"damping $g = 2\sigma/\omega$ (> 0: unstable)")
    ax_l.set_xlabel("frequency [Hz]")
    ax_l.set_ylabel(r"growth rate $\sigma$ [1/s]")
    ax_l.set_title("root locus")
    for ax in (ax_f, ax_g, ax_l):
        ax.grid(True, alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    out = args.output or os.path.join(os.path.dirname(args.csv), "flutter_locus.png")
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")


if __name__ == "__main__":
    sys.exit(main())
