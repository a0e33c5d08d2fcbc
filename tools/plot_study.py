#!/usr/bin/env python3
"""Plots of a parameter study (shellflow study): the growth rate of every point against the
parameter with its fit error and the boundary of study.json marked (study_growth.png), and
above the boundary the limit-cycle amplitude and frequency of the saturated points
(study_lco.png, only when there are some).

usage: plot_study.py OUTDIR/study.csv [--summary OUTDIR/study.json] [-o OUTDIR]
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

LABELS = {"mach": "Mach number", "density": r"free-stream density [kg/m$^3$]",
          "dynamic_pressure": "dynamic pressure [Pa]", "thickness": "thickness [m]"}


def number(text):
    return float(text) if text not in ("", "null", "nan") else math.nan


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--summary")
    ap.add_argument("-o", "--output", help="folder for the PNGs (default: the CSV's)")
    args = ap.parse_args(argv)
    out = args.output or os.path.dirname(args.csv) or "."
    summary = {}
    if args.summary and os.path.exists(args.summary):
        with open(args.summary) as f:
            summary = json.load(f)
    with open(args.csv, newline="") as f:
        reader = csv.DictReader(f)
        name = reader.fieldnames[0]
        rows = list(reader)
    ok = [r for r in rows if r["status"] == "ok"]
    failed = [r for r in rows if r["status"] != "ok"]
    x = [number(r[name]) for r in ok]
    g = [number(r["growth_rate"]) for r in ok]
    e = [number(r["growth_rate_error"]) for r in ok]
    e = [0.0 if math.isnan(v) else v for v in e]

    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.errorbar(x, g, yerr=e, fmt="o-", ms=4, capsize=3, label="time runs")
    if failed:
        ax.plot([number(r[name]) for r in failed], [0.0] * len(failed), "rx", ms=8, label="failed runs")
    ax.axhline(0.0, color="k", lw=0.8)
    b = summary.get("boundary")
    title = summary.get("case", "")
    if b is not None:
        ax.axvline(b, color="r", ls="--", lw=1.0, label=f"boundary {b:.5g}")
        title += f": boundary at {name} = {b:.5g}"
    else:
        title += ": no boundary in the range"
    ax.set_xlabel(LABELS.get(name, name))
    ax.set_ylabel(r"growth rate $\sigma$ [1/s]")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "study_growth.png"), dpi=120)
    print(f"wrote {os.path.join(out, 'study_growth.png')}")

    lco = [r for r in ok if r["saturated"] == "1" and not math.isnan(number(r["lco_amplitude"]))]
    if lco:
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
        xs = [number(r[name]) for r in lco]
        a1.plot(xs, [number(r["lco_amplitude"]) * 1e3 for r in lco], "o-")
        a2.plot(xs, [number(r["lco_frequency_hz"]) for r in lco], "o-")
        for a in (a1, a2):
            if b is not None:
                a.axvline(b, color="r", ls="--", lw=1.0)
            a.set_xlabel(LABELS.get(name, name))
            a.grid(True, alpha=0.3)
        a1.set_ylabel("limit-cycle amplitude [mm]")
        a2.set_ylabel("limit-cycle frequency [Hz]")
        fig.suptitle(summary.get("case", "") + ": limit cycles above the boundary")
        fig.tight_layout()
        fig.savefig(os.path.join(out, "study_lco.png"), dpi=120)
        print(f"wrote {os.path.join(out, 'study_lco.png')}")


if __name__ == "__main__":
    sys.exit(main())
