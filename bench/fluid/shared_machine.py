#!/usr/bin/env python3
"""Thread-parallel flow on a shared machine (issue 21, deliverable 6; docs/fluid.md "Threads on a
shared machine"): times the short variant of the default case (clamped-clamped Euler flutter,
`--set time.end=T`) at one thread, the default thread count, OMP_NUM_THREADS=2 and on 2 MPI ranks of
one thread each (`mpiexec -n 2 --bind-to none`; docs/parallel.md), on a quiet machine and with one
core taken by a busy loop (another program: a bounded Python spin, killed at
the end), and prints the medians and the ratios to the one-thread run of the same load.

usage: /usr/bin/python3 bench/fluid/shared_machine.py [--exe build/release/app/shellflow]
       [--end 0.005] [--repeat 3] [--env KEY=VALUE ...] [--mpiexec mpiexec | --mpiexec none]

--env adds variables to every timed run (e.g. --env SHELLFLOW_SPIN_US=50 to time another spin
time of the thread pool, core/parallel.h; default 20 microseconds). Each configuration runs --repeat
times, interleaved, and the median is reported (the machine is shared and noisy).
"""
import argparse
import multiprocessing
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CASE = os.path.join(ROOT, "cases", "panel_flutter", "clamped_clamped.yaml")


def spin(stop_at):
    """A busy loop on one core, bounded in time (it ends by itself if this script is killed)."""
    x = 0
    while time.time() < stop_at:
        x += 1


def timed_run(exe, end, env, folder, launcher=()):
    out = os.path.join(folder, "out")
    start = time.perf_counter()
    r = subprocess.run([*launcher, exe, "run", CASE, "-o", out, "--no-plot", "-q", "--set", f"time.end={end}"],
                       capture_output=True, text=True, env=env)
    seconds = time.perf_counter() - start
    if r.returncode != 0:
        sys.exit(f"shared_machine: the run failed:\n{r.stderr}")
    return seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--exe", default=os.path.join(ROOT, "build", "release", "app", "shellflow"))
    parser.add_argument("--end", type=float, default=0.005, help="time.end of the runs [s]")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--env", action="append", default=[], help="KEY=VALUE for every run")
    parser.add_argument("--mpiexec", default="mpiexec", help="MPI launcher of the 2-rank runs ('none': no such runs)")
    args = parser.parse_args()
    base = {k: v for k, v in os.environ.items()
            if k not in ("OMP_NUM_THREADS", "OMP_WAIT_POLICY", "GOMP_SPINCOUNT", "SHELLFLOW_SPIN_US")}
    for kv in args.env:
        key, _, value = kv.partition("=")
        base[key] = value
    configs = [("1 thread", {"OMP_NUM_THREADS": "1"}, ()), ("default", {}, ()),
               ("OMP_NUM_THREADS=2", {"OMP_NUM_THREADS": "2"}, ())]
    if args.mpiexec != "none":
        # As root (CI, containers) OpenMPI needs these; --bind-to none: the ranks may move between cores.
        ranks_env = {"OMP_NUM_THREADS": "1", "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
                     "OMPI_MCA_btl_vader_single_copy_mechanism": "none"}
        configs.append(("2 ranks x 1 thread", ranks_env, (args.mpiexec, "-n", "2", "--bind-to", "none")))
    print(f"{os.cpu_count()} cores; case {os.path.relpath(CASE, ROOT)} with time.end = {args.end} s; "
          f"{args.repeat} runs each (median); extra env: {' '.join(args.env) or 'none'}")
    with tempfile.TemporaryDirectory() as folder:
        timed_run(args.exe, args.end, {**base, "OMP_NUM_THREADS": "1"}, folder)  # the mesh cache, warm files
        for load in ("quiet", "one core busy"):
            busy = None
            if load != "quiet":
                busy = multiprocessing.Process(target=spin, args=(time.time() + 3600,), daemon=True)
                busy.start()
            try:
                times = {name: [] for name, _, _ in configs}
                for _ in range(args.repeat):
                    for name, extra, launcher in configs:
                        times[name].append(timed_run(args.exe, args.end, {**base, **extra}, folder, launcher))
            finally:
                if busy:
                    busy.terminate()
                    busy.join()
            one = statistics.median(times["1 thread"])
            print(f"\n{load}:")
            for name, _, _ in configs:
                m = statistics.median(times[name])
                print(f"  {name:<20} {m:7.2f} s  ({m / one:5.2f}x the 1-thread run)  runs: "
                      + ", ".join(f"{t:.2f}" for t in times[name]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
