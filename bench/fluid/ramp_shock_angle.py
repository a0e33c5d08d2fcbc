#!/usr/bin/env python3
"""Shock angle and wall pressure ratio of a `shellflow run cases/fluid/ramp_15deg_40k.yaml`.

Reads the last row of the run's probes.csv: the probes p_y0.3_x* sample the pressure along
y = 0.3 on the plane z = 0; the shock is where p first crosses (p1 + p2) / 2 (linear
interpolation between consecutive probes, as tests/fluid/test_ramp.cpp does between mesh
edges), and beta = atan(0.3 / x). The wall ratio is the mean of the p_wall_x* probes over
p1. Both are compared with the theta-beta-M relation (the oracle of
tests/fluid/oblique_shock.h).

  bench/fluid/ramp_shock_angle.py OUT/probes.csv [--history 100] [--check-beta 0.1]
                                  [--check-ratio 0.015]
"""
import argparse
import csv
import math
import sys


def oblique_shock(mach, theta, gamma=1.4):
    """Weak solution (beta, p2/p1) of tan(theta) = 2 cot(b) (M^2 sin^2 b - 1) / (...)."""

    def deflection(beta):
        m2s2 = (mach * math.sin(beta)) ** 2
        return math.atan(2.0 / math.tan(beta) * (m2s2 - 1.0) /
                         (mach * mach * (gamma + math.cos(2.0 * beta)) + 2.0))

    lo, hi = math.asin(1.0 / mach), 0.5 * math.pi
    for _ in range(200):  # angle of maximum deflection (golden-section-like search)
        a, b = lo + (hi - lo) / 3, hi - (hi - lo) / 3
        if deflection(a) < deflection(b):
            lo = a
        else:
            hi = b
    b_lo, b_hi = math.asin(1.0 / mach), 0.5 * (lo + hi)
    for _ in range(200):
        mid = 0.5 * (b_lo + b_hi)
        if deflection(mid) < theta:
            b_lo = mid
        else:
            b_hi = mid
    beta = 0.5 * (b_lo + b_hi)
    m2s2 = (mach * math.sin(beta)) ** 2
    return beta, 1.0 + 2.0 * gamma / (gamma + 1.0) * (m2s2 - 1.0)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("probes", help="probes.csv of the run")
    parser.add_argument("--mach", type=float, default=2.5)
    parser.add_argument("--theta", type=float, default=15.0, help="ramp angle, degrees")
    parser.add_argument("--gamma", type=float, default=1.4)
    parser.add_argument("--p1", type=float, default=1.0 / 1.4, help="free-stream pressure")
    parser.add_argument("--history", type=int, default=0,
                        help="also print beta and p2/p1 every HISTORY steps")
    parser.add_argument("--check-beta", type=float, help="fail if |beta error| exceeds this (deg)")
    parser.add_argument("--check-ratio", type=float, help="fail if |p2/p1 error| exceeds this (relative)")
    args = parser.parse_args()

    with open(args.probes, newline="") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    line_columns = sorted((float(name.split("_x")[1]), i) for i, name in enumerate(header)
                          if name.startswith("p_y0.3_x"))
    wall_columns = [i for i, name in enumerate(header) if name.startswith("p_wall_x")]
    if len(line_columns) < 2 or not wall_columns:
        sys.exit(f"{args.probes}: no p_y0.3_x* / p_wall_x* probes (run ramp_15deg_40k.yaml)")
    beta_exact, ratio_exact = oblique_shock(args.mach, math.radians(args.theta), args.gamma)
    beta_exact = math.degrees(beta_exact)
    level = 0.5 * args.p1 * (1.0 + ratio_exact)

    def measure(row):
        """(beta in degrees or None when no crossing, wall p2/p1) of one probes.csv row."""
        values = [float(v) for v in row]
        line = [(x, values[i]) for x, i in line_columns]
        beta = None
        for (xa, pa), (xb, pb) in zip(line, line[1:]):
            if pa < level <= pb:
                beta = math.degrees(math.atan2(0.3, xa + (level - pa) / (pb - pa) * (xb - xa)))
                break
        return beta, sum(values[i] for i in wall_columns) / len(wall_columns) / args.p1

    if args.history:
        print("step  beta - exact (deg)  wall p2/p1 error (%)")
        for step in range(args.history, len(rows) - 1, args.history):
            beta, ratio = measure(rows[step + 1])  # row 1 is step 0
            shown = f"{beta - beta_exact:+.3f}" if beta is not None else "no shock"
            print(f"{step:5d}  {shown:>18}  {100 * (ratio / ratio_exact - 1):+.3f}")
    beta, ratio = measure(rows[-1])
    if beta is None:
        sys.exit(f"no shock between x = {line_columns[0][0]} and {line_columns[-1][0]} on y = 0.3")
    beta_error = beta - beta_exact
    ratio_error = ratio / ratio_exact - 1.0
    print(f"{len(rows) - 2} steps: beta = {beta:.3f} deg (exact {beta_exact:.3f}, "
          f"{beta_error:+.3f} deg); wall p2/p1 = {ratio:.5f} (exact {ratio_exact:.5f}, "
          f"{100 * ratio_error:+.3f} %)")
    failed = (args.check_beta is not None and abs(beta_error) > args.check_beta) or \
             (args.check_ratio is not None and abs(ratio_error) > args.check_ratio)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
