#!/usr/bin/env python3
"""The largest stable CFL number of the coupled flutter flow (issue: sub-step speed, item 4).

Runs a coupled case (default: the paper-sized clamped-clamped Euler case) at several
fluid.analysis.cfl values for a while and reports, per value: whether the run stayed
physical (exit 0), its wall time, fluid sub-steps per shell step, and how far the panel
displacement w(t) at x = 0.6 m departs from the run at the smallest CFL (the reference):
max |w - w_ref| / max |w_ref|. Prints a Markdown table (for docs/fluid.md) and writes
cfl_study.json.

  bench/coupling/cfl_study.py [--case CASE] [--cfl 0.5 0.7 0.9 1.0] [--end 0.03] [-o OUT]
"""
import argparse
import csv
import json
import os
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--case", default=os.path.join(ROOT, "cases", "panel_flutter", "clamped_clamped.yaml"))
    ap.add_argument("--cfl", type=float, nargs="+", default=[0.5, 0.7, 0.8, 0.9, 1.0])
    ap.add_argument("--end", type=float, default=0.03, help="time.end of each run [s]")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "release", "app", "shellflow"))
    ap.add_argument("-o", "--output", default="out/cfl_study")
    args = ap.parse_args()
    rows = []
    reference = None
    for cfl in sorted(args.cfl):
        out = os.path.join(args.output, f"cfl_{cfl:g}")
        t0 = time.time()
        r = subprocess.run([args.exe, "run", args.case, "-o", out, "--no-plot", "-q", "--set",
                            f"fluid.analysis.cfl={cfl}", "--set", f"time.end={args.end}", "--set",
                            "output.every=1000000", "--set", "output.checkpoint_every=0"],
                           capture_output=True, text=True)
        wall = time.time() - t0
        with open(os.path.join(out, "probes.csv"), newline="") as f:
            probes = list(csv.DictReader(f))
        w = [float(p["w_x0600"]) for p in probes]
        with open(os.path.join(out, "coupling.csv"), newline="") as f:
            sub = [float(p["substeps"]) for p in csv.DictReader(f)]
        if reference is None:
            reference = w
        n = min(len(w), len(reference))
        scale = max(abs(x) for x in reference[:n]) or 1.0
        deviation = max(abs(a - b) for a, b in zip(w[:n], reference[:n])) / scale
        error = r.stderr.strip().splitlines()[-1] if r.returncode else ""
        rows.append({"cfl": cfl, "stable": r.returncode == 0, "t_reached": float(probes[-1]["time"]),
                     "wall_s": wall, "substeps": sum(sub) / max(len(sub), 1), "w_deviation": deviation,
                     "error": error})
        print(f"cfl {cfl}: {'stable' if r.returncode == 0 else 'FAILED'} to t = {rows[-1]['t_reached']:.4g} s, "
              f"{wall:.1f} s, {rows[-1]['substeps']:.1f} sub-steps/step, deviation {deviation:.2e} {error}",
              flush=True)
    with open(os.path.join(args.output, "cfl_study.json"), "w") as f:
        json.dump({"case": args.case, "end": args.end, "runs": rows}, f, indent=1)
    print("\n| CFL | result | t reached [s] | wall [s] | sub-steps per shell step | max \\|w − w_ref\\| / max \\|w_ref\\| |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['cfl']:g} | {'stable' if r['stable'] else 'unstable'} | {r['t_reached']:.4g} | {r['wall_s']:.1f} | "
              f"{r['substeps']:.1f} | {r['w_deviation']:.2e} |")


if __name__ == "__main__":
    main()
