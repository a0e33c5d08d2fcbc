#!/usr/bin/env python3
"""Euler-coupled panel flutter against piston theory, and its sensitivity to the numerics.

Runs variants of cases/panel_flutter/clamped_sliding.yaml (growth rate and frequency of w at
x = 0.6 m) and clamped_clamped.yaml (limit-cycle amplitude and frequency) with the
shellflow binary, next to the same cases with piston theory, and prints a Markdown table
(docs/coupling.md quotes it). Every run writes its own folder under --out.

usage: flutter_study.py [--exe build/release/app/shellflow] [--out out/flutter_study]
                        [--only NAME ...] [--end-sliding 0.08]
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CASES = os.path.join(ROOT, "cases", "panel_flutter")


sys.path.insert(0, os.path.join(ROOT, "tools"))
from plot_flutter import extrema, fit_growth  # noqa: E402  (one peak finder for plots and studies)


def growth(peaks):
    fit = fit_growth(peaks)
    return (fit[0], fit[2]) if fit else (float("nan"), float("nan"))


def run(exe, out, name, source, edits, end=None):
    with open(os.path.join(CASES, source)) as f:
        text = f.read()
    text = re.sub(r"geo: (\w+\.geo)", lambda m: "geo: " + os.path.join(CASES, m.group(1)), text)
    for old, new in edits:
        if old not in text:
            raise SystemExit(f"flutter_study: '{old}' not in {source}")
        text = text.replace(old, new)
    if end is not None:
        text = re.sub(r"end: [0-9.e-]+", f"end: {end}", text, count=1)
    folder = os.path.join(out, name)
    os.makedirs(folder, exist_ok=True)
    case = os.path.join(folder, "case.yaml")
    with open(case, "w") as f:
        f.write(text)
    start = time.time()
    r = subprocess.run([exe, "run", case, "-o", folder, "--no-plot"], capture_output=True, text=True)
    wall = time.time() - start
    if r.returncode != 0:
        print(f"{name}: failed: {r.stderr.strip().splitlines()[-1]}", file=sys.stderr)
        return None
    with open(os.path.join(folder, "probes.csv"), newline="") as f:
        rows = list(csv.reader(f))[1:]
    t = [float(x[0]) for x in rows]
    w = [float(x[1]) for x in rows]
    return t, w, wall


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "release", "app", "shellflow"))
    p.add_argument("--out", default=os.path.join("out", "flutter_study"))
    p.add_argument("--only", nargs="*")
    p.add_argument("--end-sliding", type=float, default=0.08)
    args = p.parse_args()
    es = args.end_sliding
    sliding = [
        ("sliding_piston", "clamped_sliding_piston.yaml", [], es),
        ("sliding_euler", "clamped_sliding.yaml", [], es),
        ("sliding_euler_qdif0.25", "clamped_sliding.yaml", [("q_dif: 0.5", "q_dif: 0.25")], es),
        ("sliding_euler_qdif1", "clamped_sliding.yaml", [("q_dif: 0.5", "q_dif: 1.0")], es),
        ("sliding_euler_dt5e-5", "clamped_sliding.yaml", [("step: 1.0e-4", "step: 5.0e-5")], es),
        ("sliding_euler_substeps_x2", "clamped_sliding.yaml", [("cfl: 0.5", "cfl: 0.25")], es),
        ("sliding_euler_mesh0.7", "clamped_sliding.yaml",
         [("geo: " + os.path.join(CASES, "fluid_slab.geo") + ", order: 1",
           "geo: " + os.path.join(CASES, "fluid_slab.geo") + ", order: 1, size_factor: 0.7")], es),
        ("sliding_euler_no_predictor", "clamped_sliding.yaml", [("predictor: linear", "predictor: none")], es),
    ]
    clamped = [
        ("clamped_piston", "clamped_clamped_piston.yaml", [], None),
        ("clamped_euler", "clamped_clamped.yaml", [], None),
    ]
    print("| run | growth rate [1/s] | frequency [Hz] | wall time [s] |")
    print("|---|---|---|---|")
    def runs(variants):
        """(name, t, w, wall) of every variant selected by --only that ran."""
        for name, source, edits, end in variants:
            if args.only and name not in args.only:
                continue
            r = run(args.exe, args.out, name, source, edits, end)
            if r is not None:
                yield (name, *r)

    for name, t, w, wall in runs(sliding):
        sigma, f = growth(extrema(t, w, 0.02, t[-1]))
        print(f"| {name} | {sigma:.2f} | {f:.2f} | {wall:.0f} |", flush=True)
    print()
    print("| run | limit-cycle amplitude at x = 0.6 m [mm] (last 5 cycles, spread) | frequency [Hz] | wall time [s] |")
    print("|---|---|---|---|")
    for name, t, w, wall in runs(clamped):
        peaks = extrema(t, w, 0.02, t[-1])
        last = [abs(p[1]) for p in peaks[-10:]]
        amp = sum(last) / max(1, len(last))
        spread = (max(last) - min(last)) / 2 if last else float("nan")
        _, f = growth(peaks[-10:])
        print(f"| {name} | {1e3 * amp:.2f} ± {1e3 * spread:.2f} | {f:.2f} | {wall:.0f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
