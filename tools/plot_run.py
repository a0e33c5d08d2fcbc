#!/usr/bin/env python3
"""Draw several shellflow plots in one Python process (matplotlib imported once, Agg backend).

usage: plot_run.py --job SCRIPT N ARG1 ... ARGN [--job SCRIPT N ARG1 ... ARGN ...]
Each job runs main([ARG1, ..., ARGN]) of tools/SCRIPT (one of this folder's plot_*.py), as
`python3 tools/SCRIPT ARG1 ... ARGN` would. N counts the job's arguments, so an argument may be
any string (even "--job"). A failing job (non-zero status, an exception, argparse's exit) is
reported on stderr and does not stop the others. Exit status: 0 when every job succeeded, 1
otherwise (2: the job list itself is malformed). shellflow's io::PlotRunner calls this.
"""
import importlib
import os
import re
import sys
import tempfile
import time
import traceback

sys.dont_write_bytecode = True  # importing the scripts must not write tools/__pycache__ (a run writes only its folder)

import matplotlib

matplotlib.use("Agg")
import matplotlib.figure  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

TOOLS = os.path.dirname(os.path.abspath(__file__))


def parse_jobs(argv):
    """[(script, [args...]), ...] from SCRIPT N ARG... groups; raises ValueError when malformed."""
    jobs, i = [], 0
    while i < len(argv):
        if argv[i] != "--job" or i + 2 >= len(argv):
            raise ValueError(f"expected '--job SCRIPT N ARGS...' at argument {i + 1}: {argv[i]!r}")
        script, count = argv[i + 1], argv[i + 2]
        if not re.fullmatch(r"plot_[a-z0-9_]+\.py", script) or script == "plot_run.py":
            raise ValueError(f"'{script}' is not one of the plot_*.py scripts")
        if not count.isdigit() or i + 3 + int(count) > len(argv):
            raise ValueError(f"job {script}: '{count}' is not the number of arguments that follow")
        jobs.append((script, argv[i + 3:i + 3 + int(count)]))
        i += 3 + int(count)
    return jobs


_savefig = matplotlib.figure.Figure.savefig


def savefig_without_links(fig, fname, *args, **kwargs):
    """Figure.savefig for every job: a file path is written to a new temporary of this process in
    the same folder (mkstemp: O_CREAT | O_EXCL), then renamed over the target, so a symbolic link
    named like a plot (a case bundle's `results/probes.png -> ~/.bashrc`) is replaced, never
    written through."""
    if not isinstance(fname, (str, os.PathLike)):
        return _savefig(fig, fname, *args, **kwargs)
    target = os.fspath(fname)
    if os.path.isdir(target):
        raise IsADirectoryError(f"{target}: is a folder")
    root, ext = os.path.splitext(os.path.basename(target))
    fd, tmp = tempfile.mkstemp(prefix=root + ".", suffix=ext + ".tmp", dir=os.path.dirname(target) or ".")
    try:
        with os.fdopen(fd, "wb") as f:
            kwargs.setdefault("format", ext[1:] if ext else None)
            _savefig(fig, f, *args, **kwargs)
        os.chmod(tmp, 0o644)
        os.replace(tmp, target)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


matplotlib.figure.Figure.savefig = savefig_without_links


def run_job(script, args):
    """The job's exit status (0: success)."""
    if not os.path.isfile(os.path.join(TOOLS, script)):
        print(f"plot_run: {script}: not found in {TOOLS}", file=sys.stderr)
        return 1
    saved_argv = sys.argv
    sys.argv = [script] + list(args)  # argparse's messages name the script
    try:
        module = importlib.import_module(script[:-3])
        status = module.main(list(args))
    except SystemExit as e:  # argparse's errors, sys.exit("message") in a script
        status = e.code
        if isinstance(status, str):
            print(status, file=sys.stderr)
            status = 1
    except Exception:  # noqa: BLE001 -- one job's bug must not lose the others' plots
        traceback.print_exc()
        status = 1
    finally:
        sys.argv = saved_argv
        plt.close("all")
    return 0 if status in (None, 0) else (status if isinstance(status, int) else 1)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    try:
        jobs = parse_jobs(argv)
    except ValueError as e:
        print(f"plot_run: {e}", file=sys.stderr)
        return 2
    sys.path.insert(0, TOOLS)
    failed = []
    for script, args in jobs:
        start = time.perf_counter()
        status = run_job(script, args)
        if status != 0:
            failed.append(script)
            print(f"plot_run: {script} failed (status {status})", file=sys.stderr)
        elif os.environ.get("SHELLFLOW_PLOT_TIMING"):
            print(f"plot_run: {script}: {time.perf_counter() - start:.2f} s", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
