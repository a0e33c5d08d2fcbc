#!/usr/bin/env python3
"""Flutter plots of a coupled run's probes.csv: the panel displacement probes (columns
named w_*) against time, like Figure 9 of Fernandes et al. (2014), and |w| on a log axis
with the growth rate fitted to the envelope of the extrema. When the run wrote
response.json next to probes.csv (the response analysis, docs/coupling.md), flutter.png
shows its growth rate, frequency and limit cycle.

usage: plot_flutter.py OUTDIR/probes.csv [-o OUTDIR] [--start SECONDS]
writes OUTDIR/flutter.png and OUTDIR/flutter_growth.png
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


def extrema(t, w, t0=-math.inf, t1=math.inf):
    """One extremum per half-cycle in [t0, t1] (the largest |w| between sign changes; the
    first and last, cut by the window, dropped), refined by a parabola through the sample
    and its neighbours (as coupling::fit_response)."""
    seg = []
    for i in range(len(w)):
        if t[i] < t0 or t[i] > t1 or w[i] == 0.0:
            continue
        pos = w[i] > 0
        if not seg or seg[-1][1] != pos:
            seg.append([i, pos])
        elif abs(w[i]) > abs(w[seg[-1][0]]):
            seg[-1][0] = i
    out = []
    for i, _ in seg[1:-1]:
        if i == 0 or i + 1 >= len(w):
            continue
        h0, h1 = t[i] - t[i - 1], t[i + 1] - t[i]
        d0, d1 = (w[i] - w[i - 1]) / h0, (w[i + 1] - w[i]) / h1
        a = (d1 - d0) / (h0 + h1)
        b = d0 + a * h0
        tp, wp = t[i], w[i]
        if a != 0.0 and abs(b / (2 * a)) <= max(h0, h1):
            s = -b / (2 * a)
            tp, wp = t[i] + s, w[i] + b * s + a * s * s
        out.append((tp, wp))
    return out


def fit_growth(peaks):
    """(growth rate, log-amplitude intercept, frequency) of the extrema, or None."""
    n = len(peaks)
    if n < 3:
        return None
    xs = [p[0] for p in peaks]
    ys = [math.log(abs(p[1])) for p in peaks]
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    sigma = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    c = my - sigma * mx
    half = (xs[-1] - xs[0]) / (n - 1)
    return sigma, c, 1.0 / (2.0 * half)


def read_response(path):
    """The response analysis in response.json, or None (absent or unreadable: no annotation)."""
    if not os.path.exists(path):
        return None
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        print(f"plot_flutter: {path}: ignored ({e})", file=sys.stderr)
        return None


def number(x, spec):
    return "n/a" if x is None else format(x, spec)


def response_text(r, scale, unit):
    """Two lines: growth and frequency over the window; the limit cycle, or why there is none."""
    window = r.get("window") or [None, None]
    lines = [f"{r.get('probe')}, {number(window[0], '.3g')}-{number(window[1], '.3g')} s: growth "
             f"{number(r.get('growth_rate'), '.4g')} \u00b1 {number(r.get('growth_rate_error'), '.2g')} 1/s, "
             f"{number(r.get('frequency_hz'), '.5g')} Hz ({r.get('extrema')} extrema)"]
    lco = r.get("lco")
    if lco:
        amp, spread = lco.get("amplitude"), lco.get("amplitude_spread")
        lines.append(f"limit cycle: {number(amp and amp * scale, '.3g')} \u00b1 {number(spread and spread * scale, '.2g')}"
                     f" {unit} at {number(lco.get('frequency_hz'), '.5g')} \u00b1 "
                     f"{number(lco.get('frequency_spread'), '.2g')} Hz (last {lco.get('cycles')} cycles)")
    else:
        lines.append(f"not saturated (envelope change {number(r.get('envelope_change'), '.2g')} over the last cycles)")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv")
    parser.add_argument("-o", "--outdir")
    parser.add_argument("--start", type=float, default=0.01,
                        help="fit the growth from this time on (default 0.01 s: after the start-up)")
    args = parser.parse_args(argv)
    outdir = args.outdir or os.path.dirname(args.csv) or "."
    with open(args.csv, newline="") as f:
        rows = list(csv.reader(f))
    if not rows or rows[0][0] != "time":
        print(f"plot_flutter: {args.csv}: not a probes file (first column must be 'time')", file=sys.stderr)
        return 1
    header, data = rows[0], rows[1:]
    names = [h for h in header if h.startswith("w_")] or header[1:2]
    t = [float(r[0]) for r in data]
    response = read_response(os.path.join(os.path.dirname(args.csv) or ".", "response.json"))
    fig, ax = plt.subplots(figsize=(8, 4.1 if response else 3.5))
    fig2, ax2 = plt.subplots(figsize=(8, 3.5))
    for name in names:
        w = [float(r[header.index(name)]) for r in data]
        ax.plot(t, [100 * v for v in w], label=name)
        ax2.semilogy(t, [abs(v) for v in w], lw=0.6, label=f"|{name}|")
        peaks = extrema(t, w, args.start)
        fit = fit_growth(peaks)
        if fit:
            sigma, c, freq = fit
            ax2.semilogy([p[0] for p in peaks], [abs(p[1]) for p in peaks], "o", ms=3)
            ax2.semilogy([peaks[0][0], peaks[-1][0]], [math.exp(c + sigma * peaks[0][0]),
                         math.exp(c + sigma * peaks[-1][0])], "--",
                         label=f"{name}: growth {sigma:.2f} 1/s, {freq:.1f} Hz")
    if response:
        window = response.get("window") or [None, None]
        slack = 1e-9 * (t[-1] - t[0])
        if None not in window and (window[0] > t[0] + slack or window[1] < t[-1] - slack):
            ax.axvspan(window[0], window[1], color="grey", alpha=0.1, lw=0, label="response window")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("w [cm]")
    ax.grid(True, alpha=0.3)
    ax.legend()
    ax.set_title("panel displacement")
    if response:
        # Below the axes (the data and the legend fill them).
        plotted = response.get("probe") in names  # those are drawn in cm
        fig.text(0.01, 0.01, response_text(response, 100 if plotted else 1, "cm" if plotted else ""),
                 fontsize=8, va="bottom")
        fig.tight_layout(rect=(0, 0.1, 1, 1))
    else:
        fig.tight_layout()
    fig.savefig(os.path.join(outdir, "flutter.png"), dpi=120)
    ax2.set_xlabel("t [s]")
    ax2.set_ylabel("|w| [m]")
    ax2.grid(True, which="both", alpha=0.3)
    ax2.legend(fontsize=8)
    ax2.set_title("envelope and fitted growth rate")
    fig2.tight_layout()
    fig2.savefig(os.path.join(outdir, "flutter_growth.png"), dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main())
