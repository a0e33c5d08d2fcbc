#!/usr/bin/env python3
"""Mesh and mode convergence of the 3-D plates' linear flutter boundary (docs/flutter.md,
"3-D panels"): `shellflow flutter --no-aero-damping` (mu/M -> 0) on the cases of
cases/panel_3d/ at shell grids of 6, 12 and 24 elements per side (size_factor 2, 1, 0.5;
the 2:1 rectangle has half as many across), with 24 and 48 in-vacuo modes, against the
Rayleigh-Ritz reference of tests/coupling/plate_flutter_reference.h (its converged values
are quoted below). Prints a Markdown table and each run's time.

usage: plate_flutter_convergence.py [--exe build/ci/app/shellflow] [--out out/plate_flutter]
                                    [--factors 2 1 0.5] [--modes 24 48]
"""
import argparse
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CASES = os.path.join(ROOT, "cases", "panel_3d")

# Converged Rayleigh-Ritz lambda_cr and f_cr [Hz] (test_plate_flutter_reference.cpp).
RITZ = {
    "simply_supported_square_piston": (512.633, 60.336),
    "clamped_square_piston": (851.188, 91.928),
    "rectangle_2x1_piston": (1106.59, 107.019),
    "cylindrical_panel_piston": (510.462, 64.093),
}


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "ci", "app", "shellflow"))
    ap.add_argument("--out", default=os.path.join("out", "plate_flutter"))
    ap.add_argument("--factors", type=float, nargs="+", default=[2.0, 1.0, 0.5])
    ap.add_argument("--modes", type=int, nargs="+", default=[24, 48])
    args = ap.parse_args(argv)
    print("| case | grid | modes | lambda_cr | error vs Ritz | f_cr [Hz] | time [s] |")
    print("|---|---|---|---|---|---|---|")
    for case, (ref, f_ref) in RITZ.items():
        for factor in args.factors:
            n = round(12 / factor) if "rectangle" not in case else round(8 / factor)
            grid = f"{n} x {n}" if "rectangle" not in case else f"{2 * n} x {n}"
            for modes in args.modes:
                out = os.path.join(args.out, f"{case}_{factor:g}_{modes}")
                cmd = [args.exe, "flutter", os.path.join(CASES, case + ".yaml"), "--no-aero-damping", "--json",
                       "--no-plot", "--modes", str(modes), "--set", f"meshes.shell.size_factor={factor}", "-o", out]
                t0 = time.perf_counter()
                r = subprocess.run(cmd, capture_output=True, text=True)
                seconds = time.perf_counter() - t0
                if r.returncode != 0:
                    print(f"| {case} | {grid} | {modes} | failed: {r.stderr.strip().splitlines()[-1]} |||")
                    continue
                d = json.loads(r.stdout)
                lam, f = d["lambda_cr"], d["frequency_hz"]
                print(f"| {case} | {grid} | {modes} | {lam:.2f} | {100 * (lam / ref - 1):+.2f} % | {f:.3f} "
                      f"| {seconds:.1f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
