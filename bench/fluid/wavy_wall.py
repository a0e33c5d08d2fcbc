#!/usr/bin/env python3
"""The wavy-wall tables of docs/fluid.md ("Accuracy per wavelength") and their plots.

Runs build/<preset>/bench/fluid/wavy_wall_study (one process per configuration, an argument
vector, no shell) for the Mach numbers, meshes, wall treatments, artificial viscosity and mass
matrices of the study, collects the CSV rows in OUT/wavy_wall.csv and plots the wall
pressure's amplitude error and phase against cells per lambda_x / M in OUT/wavy_wall.png.

  bench/fluid/wavy_wall.py [--study build/ci/bench/fluid/wavy_wall_study] [-o OUT]
                           [--quick]   (4 and 8 cells only, slabs only)
"""
import argparse
import csv
import io
import pathlib
import subprocess
import sys

# (label, arguments): every configuration runs at the cells given per mesh below (32 on
# slabs for the two wall treatments only).
CONFIGURATIONS = [
    ("strong walls", ["--slip-walls", "strong"]),
    ("weak walls", []),
    ("weak walls, q_dif 0.5", ["--q-dif", "0.5"]),
    ("weak walls, consistent mass", ["--consistent-mass", "3"]),
]
CELLS = {"slab": ["4", "8", "16", "32"], "unstructured": ["4", "8", "16"]}


def run(study, args):
    out = subprocess.run([str(study), "--header"] + args, check=True, capture_output=True, text=True).stdout
    return list(csv.DictReader(io.StringIO(out)))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--study", default="build/ci/bench/fluid/wavy_wall_study")
    parser.add_argument("-o", "--out", default="out/wavy_wall")
    parser.add_argument("--quick", action="store_true")
    a = parser.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for mach in ["2.3", "3.5"]:
        for mesh in ["slab"] if a.quick else ["slab", "unstructured"]:
            for label, extra in CONFIGURATIONS:
                # 32 cells (half a million tetrahedra) for the wall treatments alone
                cells = ["4", "8"] if a.quick else CELLS[mesh][:4 if label.endswith("walls") else 3]
                args = ["--mach", mach, "--cells"] + cells + extra
                if mesh == "unstructured":
                    args.append("--unstructured")
                for r in run(a.study, args):
                    r["label"] = label
                    rows.append(r)
                    print(f"M {mach} {mesh:12s} {label:28s} {r['cells_per_wavelength']:>3s} cells: amplitude "
                          f"{float(r['amplitude_ratio']):.4f}, phase {float(r['phase_deg']):+.3f} deg, loss "
                          f"{100 * float(r['loss_per_wavelength']):+.2f} %/wavelength ({r['seconds']} s)",
                          flush=True)
        # The travelling wave (V = c/2) on a deflecting mesh, weak walls, both masses.
        for extra, label in [([], "travelling, weak walls"), (["--consistent-mass", "3"],
                                                              "travelling, weak walls, consistent mass")]:
            for r in run(a.study, ["--mach", mach, "--cells", "4", "8", "16", "--wave-speed", "0.5",
                                   "--moving-mesh"] + extra):
                r["label"] = label
                rows.append(r)
    with open(out / "wavy_wall.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    plot(rows, out / "wavy_wall.png")
    print(f"wrote {out / 'wavy_wall.csv'} and {out / 'wavy_wall.png'}")


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, 2, figsize=(11, 8), sharex=True)
    for col, mach in enumerate(["2.3", "3.5"]):
        for (label, mesh), style in zip(sorted({(r["label"], r["mesh"]) for r in rows if r["mach"] == mach}),
                                        ["o-", "s-", "^-", "v-", "d-", "x-", "+-", "*-", "<-", ">-", "p-", "h-"]):
            sel = [r for r in rows if r["mach"] == mach and r["label"] == label and r["mesh"] == mesh]
            n = [float(r["cells_per_wavelength"]) for r in sel]
            amp = [max(abs(float(r["amplitude_ratio"]) - 1.0), 1e-6) * 100 for r in sel]
            phase = [max(abs(float(r["phase_deg"])), 1e-4) for r in sel]
            axes[0][col].loglog(n, amp, style, label=f"{label} ({mesh})")
            axes[1][col].loglog(n, phase, style)
        axes[0][col].set_title(f"wall pressure, M {mach}")
        axes[0][col].axhline(1.0, color="k", lw=0.5)
        axes[1][col].axhline(1.0, color="k", lw=0.5)
        axes[1][col].set_xlabel("cells per $\\lambda_x / M$")
    axes[0][0].set_ylabel("|amplitude error| [%]")
    axes[1][0].set_ylabel("|phase error| [deg]")
    axes[0][1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    sys.exit(main())
