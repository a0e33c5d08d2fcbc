#!/usr/bin/env python3
"""Coupling iterations (docs/coupling.md, "Implicit coupling"): iterations per shell step and
their cost.

Runs the shellflow binary on three cases with Aitken and IQN-ILS at the tolerances 1e-4,
1e-6 and 1e-8 (and the loose staggered scheme where it is stable), and prints a Markdown
table: mean and largest coupling iterations per step (coupling.csv), the wall time of the
steps, the time of the iterations' own work (flow mark and rewinds, shell rewinds, the
acceleration: the "coupling iterations" part of the run's wall-time line) and the cost of
one extra iteration against one loose step.

usage: coupling_iterations.py [--exe build/release/app/shellflow] [--out out/coupling_iterations]
"""
import argparse
import csv
import os
import re
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CASES = {
    # name: (case, --set overrides, the loose scheme is stable)
    "seed panel, piston theory (0.05 s)": ("panel_flutter/clamped_clamped_piston.yaml", ["time.end=0.05"], True),
    "seed panel, Euler, coarse (5 ms)": ("panel_flutter/clamped_clamped_coarse.yaml", ["time.end=0.005"], True),
    "strong case, Euler (10 ms)": ("strong_coupling/thin_sheet_dense_gas.yaml", ["time.end=0.01"], False),
}
WALL = re.compile(r"wall time ([0-9.]+) s: setup ([0-9.]+) s, .*coupling iterations ([0-9.]+) s, output ([0-9.]+) s")


def run(exe, out, case, overrides):
    args = [exe, "run", os.path.join(ROOT, "cases", case), "-o", out, "--no-plot"]
    for o in overrides:
        args += ["--set", o]
    r = subprocess.run(args, capture_output=True, text=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
    if r.returncode != 0:
        return None
    m = WALL.search(r.stderr)
    total, setup, iterations, output = (float(x) for x in m.groups())
    with open(os.path.join(out, "coupling.csv"), newline="") as f:
        k = [int(float(row["coupling_iterations"])) for row in csv.DictReader(f)]
    return {"steps": len(k), "mean": sum(k) / len(k), "max": max(k), "seconds": total - setup - output,
            "iteration_seconds": iterations}


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "release", "app", "shellflow"))
    p.add_argument("--out", default=os.path.join(ROOT, "out", "coupling_iterations"))
    a = p.parse_args()
    print("| case | scheme | tolerance | iterations per step (mean / max) | steps' wall time [s] | "
          "iterations' own work [s] | one extra iteration / one loose step |")
    print("|---|---|---|---|---|---|---|")
    for name, (case, overrides, loose_stable) in CASES.items():
        loose = None
        if loose_stable:
            loose = run(a.exe, os.path.join(a.out, "loose"), case, overrides + ["coupling.iterations=1"])
            print(f"| {name} | loose staggered | — | 1 | {loose['seconds']:.2f} | {loose['iteration_seconds']:.3f} | — |")
        for acceleration in ("aitken", "iqn_ils"):
            for tolerance in ("1e-4", "1e-6", "1e-8"):
                r = run(a.exe, os.path.join(a.out, acceleration), case,
                        overrides + ["coupling.iterations=50", f"coupling.tolerance={tolerance}",
                                     f"coupling.acceleration={acceleration}"])
                if r is None:
                    print(f"| {name} | {acceleration} | {tolerance} | failed | | | |")
                    continue
                extra = "—"
                if loose and r["mean"] > 1:
                    per_step = loose["seconds"] / loose["steps"]
                    per_extra = (r["seconds"] - loose["seconds"]) / (r["steps"] * (r["mean"] - 1))
                    extra = f"{per_extra / per_step:.2f}"
                print(f"| {name} | {acceleration} | {tolerance} | {r['mean']:.2f} / {r['max']} | {r['seconds']:.2f} | "
                      f"{r['iteration_seconds']:.3f} | {extra} |")


if __name__ == "__main__":
    main()
