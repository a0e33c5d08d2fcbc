#!/usr/bin/env python3
"""Load-displacement curves of a static shell run against reference columns.

usage: plot_load_displacement.py OUTDIR/probes.csv REFERENCE.csv [-o out.png]
       [--u COLUMN] [--w COLUMN] [--check TOLERANCE]
probes.csv: `time` holds the load factor; --u/--w name the probes of the tip displacement
components (default tip_u, tip_w). REFERENCE.csv: load_factor,minus_u_tip,w_tip (lines
starting with # are comments), e.g. cases/shell/reference_sze31.csv.
With --check TOL, exits 1 unless every reference level >= 0.1 is met to TOL relative
(levels below 0.1: 1e-3 absolute); prints the worst errors either way.
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    return rows[0], [[float(v) for v in r] for r in rows[1:]]


def interpolate(xs, ys, x):
    for i in range(1, len(xs)):
        if xs[i - 1] - 1e-12 <= x <= xs[i] + 1e-12:
            s = 0.0 if xs[i] == xs[i - 1] else (x - xs[i - 1]) / (xs[i] - xs[i - 1])
            return ys[i - 1] + s * (ys[i] - ys[i - 1])
    raise ValueError(f"load factor {x} outside the run's range")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("probes")
    p.add_argument("reference")
    p.add_argument("-o", "--output")
    p.add_argument("--u", default="tip_u")
    p.add_argument("--w", default="tip_w")
    p.add_argument("--check", type=float)
    a = p.parse_args(argv)
    header, data = read_csv(a.probes)
    _, ref = read_csv(a.reference)
    lam = [r[0] for r in data]
    minus_u = [-r[header.index(a.u)] for r in data]
    w = [r[header.index(a.w)] for r in data]

    worst = {"-U": 0.0, "W": 0.0}
    ok = True
    for level, ref_u, ref_w in ref:
        for name, values, exact in (("-U", minus_u, ref_u), ("W", w, ref_w)):
            got = interpolate(lam, values, level)
            if abs(exact) >= 0.1:
                err = abs(got - exact) / abs(exact)
                ok &= a.check is None or err <= a.check
            else:
                err = abs(got - exact)
                ok &= a.check is None or err <= 1e-3
            worst[name] = max(worst[name], err)
    print(f"worst error: -U {worst['-U']:.3e}, W {worst['W']:.3e} (relative; absolute below 0.1)")

    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.plot(minus_u, lam, "b-", label="-U (shellflow)")
    ax.plot(w, lam, "r-", label="W (shellflow)")
    ax.plot([r[1] for r in ref], [r[0] for r in ref], "bo", mfc="none", label="-U reference")
    ax.plot([r[2] for r in ref], [r[0] for r in ref], "rs", mfc="none", label="W reference")
    ax.set_xlabel("tip displacement")
    ax.set_ylabel("load factor")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    out = a.output or a.probes.rsplit(".", 1)[0] + "_load_displacement.png"
    fig.savefig(out, dpi=120)
    print(f"plot_load_displacement: wrote {out}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
