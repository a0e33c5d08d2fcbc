#!/usr/bin/env python3
"""Cost growth of the shell in a 3-D plate run (docs/performance.md, "3-D plates"): the
clamped square in piston theory (cases/panel_3d/clamped_square_piston.yaml, Mach 3.5) on
8 x 8, 16 x 16 and 32 x 32 grids of cubic triangles' squares (size_factor 1.5, 0.75, 0.375),
a fixed number of shell steps each; prints the shell's dofs, its time per step (setup and
the first step's factorisation included, as a run has them), the Newton iterations per step
and the wall time, as a Markdown table. One thread unless OMP_NUM_THREADS says otherwise.

usage: plate_cost.py [--exe build/ci/app/shellflow] [--out out/plate_cost] [--end 0.01]
                     [--factors 1.5 0.75 0.375]
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CASE = os.path.join(ROOT, "cases", "panel_3d", "clamped_square_piston.yaml")


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "ci", "app", "shellflow"))
    ap.add_argument("--out", default=os.path.join("out", "plate_cost"))
    ap.add_argument("--end", type=float, default=0.01, help="simulated time per grid [s] (1e-4 s steps)")
    ap.add_argument("--factors", type=float, nargs="+", default=[1.5, 0.75, 0.375])
    args = ap.parse_args(argv)
    env = dict(os.environ)
    env.setdefault("OMP_NUM_THREADS", "1")
    print(f"threads: {env['OMP_NUM_THREADS']}, {args.end} s of flow per grid (1e-4 s steps)")
    print("| grid | shell nodes | dofs | shell time per step [ms] | Newton iterations per step | wall [s] |")
    print("|---|---|---|---|---|---|")
    for factor in args.factors:
        n = round(12 / factor)
        out = os.path.join(args.out, f"grid_{n}")
        cmd = [args.exe, "run", CASE, "--no-plot", "-o", out, "--set", "fluid.free_stream.mach=3.5", "--set",
               f"time.end={args.end}", "--set", f"meshes.shell.size_factor={factor}"]
        t0 = time.perf_counter()
        r = subprocess.run(cmd, capture_output=True, text=True, env=env)
        wall = time.perf_counter() - t0
        if r.returncode != 0:
            print(f"| {n} x {n} | failed: {r.stderr.strip().splitlines()[-1]} |||||")
            continue
        nodes = int(re.search(r"shell (\d+) nodes", r.stderr).group(1))
        shell = float(re.search(r"shell ([0-9.]+) s, fluid mesh motion", r.stderr).group(1))
        with open(os.path.join(out, "coupling.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        newton = sum(int(row["newton_iterations"]) for row in rows) / len(rows)
        print(f"| {n} x {n} | {nodes} | {7 * nodes} | {1000 * shell / len(rows):.1f} | {newton:.2f} | {wall:.1f} |",
              flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
