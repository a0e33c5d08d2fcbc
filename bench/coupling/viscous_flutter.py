#!/usr/bin/env python3
"""Viscous panel flutter (docs/coupling.md, "Viscous traction"): the clamped-sliding panel at
Mach 2.3 with and without viscosity, on the coarse and the paper-sized fluid meshes.

Each pair runs the same mesh, shock capturing (q_dif 1.0) and CFL (0.5) for 0.14 s; only the
gas differs (Euler with slip walls, or Sutherland air with adiabatic no-slip walls and a
cavity vented to that mesh's mean steady panel pressure). Prints a Markdown table: growth rate
and frequency of w at x = 0.6 m fitted on [0.04, 0.14] s (response.json), the difference, and
the wall time.

usage: viscous_flutter.py [--exe build/ci/app/shellflow] [--out out/viscous_flutter] [--fine]
"""
import argparse
import json
import os
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
COMMON = ["time.end=0.14", "coupling.response.window=[0.04, 1.0]", "coupling.response.probe=w_x0600",
          "fluid.analysis.q_dif=1.0", "fluid.analysis.cfl=0.5"]
RUNS = [
    # (mesh, gas, case, further overrides)
    ("coarse (size 2)", "inviscid", "panel_flutter/clamped_sliding_coarse.yaml", []),
    ("coarse (size 2)", "viscous", "viscous_coupling/flutter_viscous_coarse.yaml", []),
    ("paper (size 1)", "inviscid", "panel_flutter/clamped_sliding.yaml", []),
    ("paper (size 1)", "viscous", "viscous_coupling/flutter_viscous.yaml", []),
]
# --fine: the paper mesh at size factor 0.7, the cavity vented to that mesh's mean steady
# panel pressure (28905.89 Pa, measured as for the cases: the viscous flow over the rigid
# panel, q_dif 1.0, 20 ms).
FINE = [
    ("fine (size 0.7)", "inviscid", "panel_flutter/clamped_sliding.yaml", ["meshes.fluid.size_factor=0.7"]),
    ("fine (size 0.7)", "viscous", "viscous_coupling/flutter_viscous.yaml",
     ["meshes.fluid.size_factor=0.7", "coupling.cavity_pressure.value=28905.89*(1 - 0.001*step(0.004 - t))"]),
]


def run(exe, out, case, overrides):
    args = [exe, "run", os.path.join(ROOT, "cases", case), "-o", out, "--no-plot"]
    for o in COMMON + overrides:
        args += ["--set", o]
    start = time.monotonic()
    r = subprocess.run(args, capture_output=True, text=True)
    seconds = time.monotonic() - start
    if r.returncode != 0:
        return None, seconds, r.stderr.strip().splitlines()[-1]
    with open(os.path.join(out, "response.json")) as f:
        return json.load(f), seconds, ""


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "ci", "app", "shellflow"))
    p.add_argument("--out", default=os.path.join(ROOT, "out", "viscous_flutter"))
    p.add_argument("--fine", action="store_true", help="only the fine mesh's pair (about 25 min per run)")
    a = p.parse_args()
    rows, results = [], {}
    for mesh, gas, case, overrides in FINE if a.fine else RUNS:
        response, seconds, error = run(a.exe, os.path.join(a.out, f"{mesh.split()[0]}_{gas}"), case, overrides)
        results[(mesh, gas)] = response
        if response is None:
            rows.append(f"| {mesh} | {gas} | failed: {error} | | | {seconds:.0f} |")
            continue
        extra = ""
        if gas == "viscous" and results.get((mesh, "inviscid")):
            ref = results[(mesh, "inviscid")]
            extra = (f"{100 * (response['growth_rate'] / ref['growth_rate'] - 1):+.1f} % / "
                     f"{100 * (response['frequency_hz'] / ref['frequency_hz'] - 1):+.2f} %")
        rows.append(f"| {mesh} | {gas} | {response['growth_rate']:.2f} | {response['frequency_hz']:.2f} | {extra} | "
                    f"{seconds:.0f} |")
        print(rows[-1], flush=True)
    print("| fluid mesh | gas | growth rate (1/s) | frequency (Hz) | viscous - inviscid (growth / frequency) | "
          "wall time (s) |")
    print("|---|---|---|---|---|---|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
