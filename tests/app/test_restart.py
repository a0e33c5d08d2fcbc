#!/usr/bin/env python3
"""Checkpoint and restart of `shellflow run` (docs/restart.md), run by CTest.

Every kind of time-stepping run is run straight through and in pieces (stopped with a
checkpoint, restarted from it); every output file must be byte-identical, with 1 and 2
OpenMP threads. Signals, refusals and random SIGKILLs are tested on the same cases.
The executable comes from $SHELLFLOW_EXE.
"""
import csv
import fcntl
import os
import random
import signal
import struct
import subprocess
import tempfile
import time
import unittest
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXE = os.environ.get("SHELLFLOW_EXE", os.path.join(ROOT, "build", "release", "app", "shellflow"))
CASES = os.path.join(ROOT, "cases")
STOPPED = 75  # the exit code of a run stopped with a checkpoint

# The five kinds of run, each short: (case, --set overrides, steps of the first piece).
RUNS = {
    "shell_dynamics": ("shell/strip_free_vibration.yaml", ["time.end=0.02", "output.every=7"], 17),
    "flow": ("fluid/sod.yaml", ["time.end=0.05", "output.every=3"], 20),
    "mesh_motion": ("motion/panel_single_mode_laplace.yaml", ["output.every=3"], 7),
    "piston_coupled": ("panel_flutter/clamped_clamped_piston.yaml", ["time.end=0.01", "output.every=7"], 33),
    "euler_coupled": ("panel_flutter/clamped_clamped_coarse.yaml", ["time.end=0.002", "output.every=3"], 7),
    # Coupling iterations: the restart must carry the acceleration's history (IQN-ILS columns
    # of past steps, Aitken's factor) to stay bit-exact.
    "iqn_ils_coupled": ("strong_coupling/thin_sheet_dense_gas.yaml", ["time.end=0.002", "output.every=3"], 9),
    # The shear of a no-slip wet wall is part of the exchanged loads (the predictor's history).
    "viscous_coupled": ("viscous_coupling/flutter_viscous_coarse.yaml", ["time.end=0.002", "output.every=3"], 7),
    "aitken_coupled": ("panel_flutter/clamped_clamped_piston.yaml",
                       ["time.end=0.005", "output.every=7", "coupling.iterations=20", "coupling.tolerance=1e-9",
                        "coupling.acceleration=aitken"], 21),
}
PISTON = os.path.join(CASES, "panel_flutter", "clamped_clamped_piston.yaml")


def shellflow(*args, threads=None, **kwargs):
    env = dict(os.environ)
    if threads:
        env["OMP_NUM_THREADS"] = str(threads)
    return subprocess.run([EXE, *args], capture_output=True, text=True, timeout=900, env=env, **kwargs)


def sets(overrides):
    return [a for o in overrides for a in ("--set", o)]


def outputs(folder):
    """{name: bytes} of every file of a run's folder but its checkpoints and its lock file (which
    holds the pid of a run killed while it held it)."""
    files = {}
    for name in sorted(os.listdir(folder)):
        if not name.startswith("checkpoint_") and name != ".shellflow.lock":
            with open(os.path.join(folder, name), "rb") as f:
                files[name] = f.read()
    return files


def snapshot(folder):
    """Names, sizes, modification times and bytes of every file: a folder left untouched keeps them.
    Not the lock file, which every process that works in the folder takes (.shellflow.lock: the
    holder's pid while it runs)."""
    files = {}
    for n in sorted(os.listdir(folder)):
        if n == ".shellflow.lock":
            continue
        with open(os.path.join(folder, n), "rb") as f:
            files[n] = (os.stat(os.path.join(folder, n)).st_mtime_ns, f.read())
    return files


def checksum64(data, seed=0xcbf29ce484222325):
    """core/archive.cpp's checksum64, written again."""
    mask, prime, h, n = (1 << 64) - 1, 0x100000001b3, seed, len(data)
    words = n // 8
    for (w,) in struct.iter_unpack("<Q", data[:8 * words]):
        h = ((h ^ w) * prime) & mask
        h ^= h >> 29
    for c in data[8 * words:]:
        h = ((h ^ c) * prime) & mask
    h ^= n
    return (h * prime) & mask


MAGIC = b"shellflow checkpoint\n"


def read_checkpoint(path):
    with open(path, "rb") as f:
        data = f.read()
    assert data.startswith(MAGIC)
    fmt, header_bytes, payload_bytes, checksum = struct.unpack_from("<IQQQ", data, len(MAGIC))
    start = len(MAGIC) + 28
    header = data[start:start + header_bytes]
    payload = data[start + header_bytes:]
    assert len(payload) == payload_bytes
    return fmt, header, payload, checksum


def write_checkpoint(path, fmt, header, payload):
    checksum = checksum64(payload, checksum64(header))
    with open(path, "wb") as f:
        f.write(MAGIC + struct.pack("<IQQQ", fmt, len(header), len(payload), checksum) + header + payload)


def assert_readable(test, folder):
    """Every .pvd parses and every .vtu it lists is complete; probes.csv has whole rows."""
    for name in os.listdir(folder):
        if name.endswith(".pvd"):
            for d in ET.parse(os.path.join(folder, name)).getroot().iter("DataSet"):
                with open(os.path.join(folder, d.get("file")), "rb") as f:
                    vtu = f.read()
                test.assertTrue(vtu.startswith(b"<?xml") and vtu.rstrip().endswith(b"</VTKFile>"), d.get("file"))
        if name.endswith(".csv"):
            with open(os.path.join(folder, name), newline="") as f:
                text = f.read()
            test.assertTrue(text.endswith("\n"), name)
            rows = list(csv.reader(text.splitlines()))
            test.assertTrue(all(len(r) == len(rows[0]) for r in rows), name)
            for r in rows[1:]:
                [float(x) for x in r]


class RestartRuns(unittest.TestCase):
    """Run N steps straight; run k, stop, restart, run to N: the same bytes everywhere."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name

    def tearDown(self):
        self.tmp.cleanup()

    def straight_and_in_pieces(self, kind, threads):
        """threads: one count for the three runs, or (straight, first piece, restart)."""
        case, overrides, k = RUNS[kind]
        case = os.path.join(CASES, case)
        straight, first, second = threads if isinstance(threads, tuple) else (threads,) * 3
        tag = "_".join(str(t) for t in (straight, first, second))
        full, part = (os.path.join(self.dir, f"{kind}_{tag}_{x}") for x in ("full", "part"))
        r = shellflow("run", case, "-o", full, "--no-plot", *sets(overrides), threads=straight)
        self.assertEqual(r.returncode, 0, r.stderr)
        r = shellflow("run", case, "-o", part, "--no-plot", "--stop-after", str(k), *sets(overrides), threads=first)
        self.assertEqual(r.returncode, STOPPED, r.stderr)
        self.assertIn(f"at step {k}", r.stderr)
        self.assertIn(f"continue with: shellflow run {case} --restart {part}", r.stderr)
        self.assertTrue(os.path.exists(os.path.join(part, f"checkpoint_{k:06}.ckpt")))
        assert_readable(self, part)
        r = shellflow("run", case, "--restart", part, "--no-plot", *sets(overrides), threads=second)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("another build", r.stderr)
        self.assertNotIn("warning", r.stderr.lower())
        a, b = outputs(full), outputs(part)
        self.assertEqual(sorted(a), sorted(b))
        for name in a:
            self.assertTrue(a[name] == b[name], f"{kind}, {threads} thread(s): {name} differs")
        self.assertGreater(len([n for n in a if n.endswith(".vtu")]), 3)

    def test_shell_dynamics(self):
        for threads in (1, 2):
            self.straight_and_in_pieces("shell_dynamics", threads)

    def test_flow(self):
        for threads in (1, 2):
            self.straight_and_in_pieces("flow", threads)

    def test_mesh_motion_with_the_laplace_movers_warm_start(self):
        for threads in (1, 2):
            self.straight_and_in_pieces("mesh_motion", threads)

    def test_piston_theory_coupled(self):
        for threads in (1, 2):
            self.straight_and_in_pieces("piston_coupled", threads)

    def test_euler_coupled_flutter(self):
        for threads in (1, 2):
            self.straight_and_in_pieces("euler_coupled", threads)

    def test_euler_coupled_flutter_restarted_on_other_thread_counts(self):
        # The sums do not depend on the thread count (docs/parallel.md): straight on one thread,
        # stopped on two, restarted on three, the same bytes.
        self.straight_and_in_pieces("euler_coupled", (1, 2, 3))

    def test_implicit_coupling_iqn_ils(self):
        for threads in (1, 2):
            self.straight_and_in_pieces("iqn_ils_coupled", threads)

    def test_viscous_coupled_flutter(self):
        self.straight_and_in_pieces("viscous_coupled", 1)

    def test_implicit_coupling_aitken(self):
        self.straight_and_in_pieces("aitken_coupled", 1)

    def test_three_pieces_periodic_checkpoints_and_an_older_checkpoint(self):
        overrides = ["time.end=0.01", "output.every=7", "output.checkpoint_every=10"]
        full, part = os.path.join(self.dir, "full"), os.path.join(self.dir, "part")
        r = shellflow("run", PISTON, "-o", full, "--no-plot", *sets(overrides))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("checkpoints: 10 written", r.stderr)
        # The two newest are kept.
        self.assertEqual(sorted(n for n in os.listdir(full) if n.startswith("checkpoint_")),
                         ["checkpoint_000090.ckpt", "checkpoint_000100.ckpt"])
        r = shellflow("run", PISTON, "-o", part, "--no-plot", "--stop-after", "45", *sets(overrides))
        self.assertEqual(r.returncode, STOPPED, r.stderr)
        # From the older periodic checkpoint (step 40, not the stop's at 45), then on.
        r = shellflow("run", PISTON, "--restart", os.path.join(part, "checkpoint_000040.ckpt"), "--no-plot",
                      "--stop-after", "23", *sets(overrides))
        self.assertEqual(r.returncode, STOPPED, r.stderr)
        self.assertIn("at step 63", r.stderr)
        r = shellflow("run", PISTON, "--restart", part, "--no-plot", *sets(overrides))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(outputs(full), outputs(part))

    def test_a_run_killed_after_its_last_checkpoint_is_finished_by_a_restart(self):
        # A kill between the last step's checkpoint and the end-of-run files (response.json of a
        # shell run; a flow run writes nothing after its last step): --restart of that checkpoint
        # makes no step and writes them, the same bytes as the run that was not killed.
        for case, overrides, ends in (
                (PISTON, ["time.end=0.01", "output.every=7", "output.checkpoint_every=50"], ["response.json"]),
                (os.path.join(CASES, RUNS["flow"][0]), RUNS["flow"][1] + ["output.checkpoint_every=1"], [])):
            full, part = (os.path.join(self.dir, os.path.basename(case) + x) for x in ("_full", "_part"))
            r = shellflow("run", case, "-o", full, "--no-plot", *sets(overrides))
            self.assertEqual(r.returncode, 0, r.stderr)
            r = shellflow("run", case, "-o", part, "--no-plot", *sets(overrides))
            self.assertEqual(r.returncode, 0, r.stderr)
            for name in ends:
                os.remove(os.path.join(part, name))
            r = shellflow("run", case, "--restart", part, "--no-plot", *sets(overrides))
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("is the last of this run: no step to make; writing its end-of-run files", r.stderr)
            self.assertEqual(outputs(full), outputs(part), case)

    def test_a_longer_time_end_continues_a_finished_run(self):
        overrides = ["output.every=7", "output.checkpoint_every=50"]
        full, part = os.path.join(self.dir, "full"), os.path.join(self.dir, "part")
        r = shellflow("run", PISTON, "-o", full, "--no-plot", "--set", "time.end=0.02", *sets(overrides))
        self.assertEqual(r.returncode, 0, r.stderr)
        r = shellflow("run", PISTON, "-o", part, "--no-plot", "--set", "time.end=0.01", *sets(overrides))
        self.assertEqual(r.returncode, 0, r.stderr)
        r = shellflow("run", PISTON, "--restart", part, "--no-plot", "--set", "time.end=0.02", *sets(overrides))
        self.assertEqual(r.returncode, 0, r.stderr)
        a, b = outputs(full), outputs(part)
        # The shorter run's last frame (step 100, not a multiple of 7) stays in its series.
        self.assertEqual(sorted(set(b) - set(a)), ["shell_000100.vtu"])
        for name in ("probes.csv", "coupling.csv", "response.json", "shell_000105.vtu", "shell_000200.vtu"):
            self.assertTrue(a[name] == b[name], name)


class RestartSignals(unittest.TestCase):
    """SIGINT/SIGTERM finish the step, write a checkpoint and exit 75; --stop-at-wall too."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name
        self.overrides = ["time.end=0.05", "output.every=20"]
        self.full = os.path.join(self.dir, "full")
        r = shellflow("run", PISTON, "-o", self.full, "--no-plot", *sets(self.overrides))
        self.assertEqual(r.returncode, 0, r.stderr)

    def tearDown(self):
        self.tmp.cleanup()

    def start(self, out, *extra):
        return subprocess.Popen([EXE, "run", PISTON, "-o", out, "--no-plot", *sets(self.overrides), *extra],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    @staticmethod
    def wait_for_rows(out, rows, timeout=60):
        end = time.time() + timeout
        path = os.path.join(out, "probes.csv")
        while time.time() < end:
            if os.path.exists(path):
                with open(path) as f:
                    if len(f.readlines()) > rows:
                        return
            time.sleep(0.005)
        raise AssertionError(f"{path}: fewer than {rows} rows after {timeout} s")

    def restart_and_compare(self, out):
        r = shellflow("run", PISTON, "--restart", out, "--no-plot", *sets(self.overrides))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(outputs(self.full), outputs(out))

    def test_sigint_and_sigterm_stop_at_a_step_with_a_checkpoint(self):
        for sig, name in ((signal.SIGINT, "SIGINT"), (signal.SIGTERM, "SIGTERM")):
            out = os.path.join(self.dir, name)
            p = self.start(out)
            self.wait_for_rows(out, 50)
            p.send_signal(sig)
            _, err = p.communicate(timeout=120)
            self.assertEqual(p.returncode, STOPPED, err)
            self.assertIn(f"stopped on {name} at step", err)
            self.assertIn("--restart", err)
            assert_readable(self, out)
            self.restart_and_compare(out)

    def test_two_signals_leave_a_readable_folder_that_restarts(self):
        out = os.path.join(self.dir, "twice")
        p = self.start(out, "--set", "output.checkpoint_every=1")
        self.wait_for_rows(out, 50)
        p.send_signal(signal.SIGINT)
        time.sleep(1.2)  # within a second a second signal is taken for the same one
        p.send_signal(signal.SIGINT)
        p.communicate(timeout=120)
        # Either the second signal came in time (killed by it) or the run had already stopped.
        self.assertIn(p.returncode, (-signal.SIGINT, STOPPED))
        assert_readable(self, out)
        self.restart_and_compare(out)

    def assert_same_study(self, straight, other):
        for point in ("mach_1.95", "mach_2.1"):
            a = outputs(os.path.join(straight, "points", point))
            b = outputs(os.path.join(other, "points", point))
            for name in ("probes.csv", "coupling.csv", "response.json", "shell.pvd"):
                self.assertTrue(a[name] == b[name], f"{other}: {point}/{name}")
        with open(os.path.join(straight, "study.csv")) as f, open(os.path.join(other, "study.csv")) as g:
            self.assertEqual(f.read(), g.read(), other)

    def test_an_interrupted_killed_or_locked_out_study_continues_to_the_same_result(self):
        # One study three ways, each ending with the straight study's points and study.csv:
        # Ctrl-C (the study and its runs stop with checkpoints, exit 75); SIGKILL to the study
        # alone (its runs get SIGTERM from the kernel, stop with checkpoints and release their
        # folders); a point folder locked by another process (the point is not recorded as failed:
        # the study exits 1 naming it, and the same command runs it once the lock is gone).
        case = os.path.join(CASES, "panel_flutter", "clamped_sliding_piston_monolithic.yaml")
        args = ["--no-plot", "-j", "2", "--set", "study.range=[1.95, 2.1]", "--set", "study.points=2",
                "--set", "study.max_refinements=0", "--set", "study.set={time.end: 0.06}"]
        straight = os.path.join(self.dir, "study_straight")
        r = shellflow("study", case, "-o", straight, *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        for how in ("ctrl-c", "sigkill"):
            out = os.path.join(self.dir, "study_" + how)
            p = subprocess.Popen([EXE, "study", case, "-o", out, *args], stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE, text=True, start_new_session=True)
            self.wait_for_rows(os.path.join(out, "points", "mach_1.95"), 100)
            if how == "ctrl-c":
                os.killpg(p.pid, signal.SIGINT)  # a terminal's Ctrl-C: the study and its runs
                _, err = p.communicate(timeout=120)
                self.assertEqual(p.returncode, STOPPED, err)
                self.assertIn("stopped with a checkpoint", err)
                self.assertIn("run the same command again to continue", err)
            else:
                p.kill()
                p.communicate(timeout=60)
                for point in ("mach_1.95", "mach_2.1"):  # the orphaned runs end with checkpoints
                    lock = os.path.join(out, "points", point, ".shellflow.lock")
                    with open(lock, "a") as f:
                        end = time.time() + 60
                        while True:
                            try:
                                fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
                                break
                            except BlockingIOError:
                                self.assertLess(time.time(), end, f"{lock}: still held 60 s after the study died")
                                time.sleep(0.05)
                    with open(os.path.join(out, "points", point, "run.log")) as f:
                        self.assertIn("stopped on SIGTERM at step", f.read())
            r = shellflow("study", case, "-o", out, *args)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("(continued from its checkpoint)", r.stderr)
            self.assert_same_study(straight, out)
        locked = os.path.join(self.dir, "study_locked")
        point = os.path.join(locked, "points", "mach_2.1")
        os.makedirs(point)
        with open(os.path.join(point, ".shellflow.lock"), "w") as f:
            f.write(f"{os.getpid()}\n")
            f.flush()
            fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
            r = shellflow("study", case, "-o", locked, *args)
        self.assertEqual(r.returncode, 1, r.stderr)
        self.assertIn("mach = 2.1 failed, not for the physics: ", r.stderr)
        self.assertIn(f"another shellflow process (pid {os.getpid()})", r.stderr)
        self.assertIn("shellflow: error: study: 1 point(s) failed for reasons other than the physics and were not "
                      "recorded: mach = 2.1 (", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(point, "point.json")))
        self.assertTrue(os.path.exists(os.path.join(locked, "points", "mach_1.95", "point.json")))
        r = shellflow("study", case, "-o", locked, *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("mach = 1.95 already done (ok), not rerun", r.stderr)
        self.assert_same_study(straight, locked)

    def test_stop_at_wall(self):
        out = os.path.join(self.dir, "wall")
        r = shellflow("run", PISTON, "-o", out, "--no-plot", "--stop-at-wall", "0.3", *sets(self.overrides))
        self.assertEqual(r.returncode, STOPPED, r.stderr)
        self.assertIn("stopped at --stop-at-wall at step", r.stderr)
        self.restart_and_compare(out)


class RestartRefusals(unittest.TestCase):
    """Each refusal: one line naming the checkpoint and the cause, exit 1, the folder untouched."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.out = os.path.join(cls.tmp.name, "out")
        cls.overrides = ["time.end=0.005", "output.every=7"]
        r = shellflow("run", PISTON, "-o", cls.out, "--no-plot", "--stop-after", "20", *sets(cls.overrides))
        assert r.returncode == STOPPED, r.stderr
        cls.checkpoint = os.path.join(cls.out, "checkpoint_000020.ckpt")
        with open(cls.checkpoint, "rb") as f:
            cls.good = f.read()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def tearDown(self):
        with open(self.checkpoint, "wb") as f:
            f.write(self.good)

    def refused(self, needle, *args, restart=None, after_setup=False):
        """`after_setup`: refused once the run is set up (its payload read), after the set-up's log."""
        before = snapshot(self.out)
        r = shellflow("run", PISTON, "--restart", restart or self.out, "--no-plot", *sets(self.overrides), *args)
        self.assertEqual(r.returncode, 1, r.stderr)
        lines = r.stderr.strip().splitlines()
        if after_setup:
            self.assertTrue(all(" info: " in line for line in lines[:-1]), r.stderr)
            lines = lines[-1:]
        self.assertEqual(len(lines), 1, r.stderr)
        self.assertTrue(lines[0].startswith("shellflow: error: "), lines[0])
        self.assertIn(needle, lines[0])
        self.assertEqual(snapshot(self.out), before, "the refusal changed the output folder")
        return lines[0]

    def test_another_case(self):
        line = self.refused("the case changed since the checkpoint was written (sections: fluid, shell)",
                            "--set", "shell.thickness=1.4e-3", "--set", "fluid.free_stream.mach=2.4")
        self.assertIn(self.checkpoint, line)

    def test_another_case_name(self):
        self.refused("a checkpoint of case 'clamped_clamped_piston', not of 'other'", "--set", "name=other")

    def test_another_program_version(self):
        fmt, header, payload, _ = read_checkpoint(self.checkpoint)
        (n,) = struct.unpack_from("<Q", header)
        version = header[8:8 + n].decode()
        other = b"9.9.9"
        write_checkpoint(self.checkpoint, fmt, struct.pack("<Q", len(other)) + other + header[8 + n:], payload)
        self.refused(f"written by shellflow 9.9.9, this is shellflow {version}")

    def craft_header_step(self, step):
        """The checkpoint with its header's step replaced and a valid checksum: the checksum is no
        signature, anyone can write one."""
        fmt, header, payload, _ = read_checkpoint(self.checkpoint)
        (n,) = struct.unpack_from("<Q", header)  # program version
        (m,) = struct.unpack_from("<Q", header, 8 + n + 8)  # case name, after the build id
        at = 8 + n + 8 + 8 + m
        write_checkpoint(self.checkpoint, fmt, header[:at] + struct.pack("<q", step) + header[at + 8:], payload)

    def test_a_crafted_checkpoint_with_a_step_out_of_range(self):
        for step in (-1000000, 2**63 - 1):
            self.craft_header_step(step)
            self.refused(f"damaged (step {step}")

    def test_a_crafted_checkpoint_whose_step_is_not_its_name(self):
        self.craft_header_step(10)
        self.refused("holds step 10, its name says step 20")

    def test_a_crafted_checkpoint_with_a_series_entry_outside_the_folder(self):
        fmt, header, payload, _ = read_checkpoint(self.checkpoint)
        name, evil = b"shell_000000.vtu", b"../../evil.vtu"
        entry = struct.pack("<Q", len(name)) + name
        self.assertIn(entry, payload)
        write_checkpoint(self.checkpoint, fmt, header, payload.replace(entry, struct.pack("<Q", len(evil)) + evil, 1))
        self.refused("damaged (entry '../../evil.vtu' at t = 0 of shell.pvd is not a file of the output folder)",
                     after_setup=True)

    def test_a_time_end_before_the_checkpoint(self):
        self.refused("step 20 (t = 0.002 s) is after time.end = 0.001 s of this run; raise time.end",
                     "--set", "time.end=0.001")

    def test_a_truncated_checkpoint(self):
        with open(self.checkpoint, "wb") as f:
            f.write(self.good[:len(self.good) // 2])
        self.refused("truncated")

    def test_a_corrupted_checkpoint(self):
        bad = bytearray(self.good)
        bad[len(bad) * 2 // 3] ^= 0x04
        with open(self.checkpoint, "wb") as f:
            f.write(bad)
        self.refused("checksum mismatch")

    def test_the_checksum_is_the_documented_one(self):
        fmt, header, payload, checksum = read_checkpoint(self.checkpoint)
        self.assertEqual(checksum64(payload, checksum64(header)), checksum)

    def test_a_missing_checkpoint(self):
        self.refused("no such checkpoint", restart=os.path.join(self.out, "checkpoint_000999.ckpt"))
        empty = os.path.join(self.tmp.name, "empty")
        os.makedirs(empty, exist_ok=True)
        self.refused("no checkpoint_NNNNNN.ckpt in this directory", restart=empty)

    def test_another_output_folder(self):
        self.refused("drop -o", "-o", os.path.join(self.tmp.name, "elsewhere"))

    def test_changed_mesh_geometry(self):
        folder = os.path.join(self.tmp.name, "case")
        os.makedirs(folder, exist_ok=True)
        src = os.path.join(CASES, "panel_flutter")
        for name in ("clamped_clamped_piston.yaml", "panel_strip.geo"):
            with open(os.path.join(src, name)) as f, open(os.path.join(folder, name), "w") as g:
                g.write(f.read())
        case = os.path.join(folder, "clamped_clamped_piston.yaml")
        out = os.path.join(self.tmp.name, "mesh_out")
        r = shellflow("run", case, "-o", out, "--no-plot", "--stop-after", "5", *sets(self.overrides))
        self.assertEqual(r.returncode, STOPPED, r.stderr)
        geo = os.path.join(folder, "panel_strip.geo")
        with open(geo) as f:
            text = f.read()
        with open(geo, "w") as f:
            f.write(text.replace("x_te = 0.75;", "x_te = 0.76;"))
        before = snapshot(out)
        r = shellflow("run", case, "--restart", out, "--no-plot", *sets(self.overrides))
        self.assertEqual(r.returncode, 1, r.stderr)
        self.assertIn("sections: mesh shell", r.stderr.strip().splitlines()[-1])
        self.assertEqual(snapshot(out), before)

    def test_a_static_analysis_has_no_checkpoints(self):
        case = os.path.join(CASES, "shell", "oblique_strip_hard_support.yaml")
        with tempfile.TemporaryDirectory() as out:
            r = shellflow("run", case, "-o", out, "--no-plot", "--stop-after", "1")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("a static analysis is not checkpointed", r.stderr)
            r = shellflow("run", case, "--restart", out, "--no-plot")
            self.assertEqual(r.returncode, 1, r.stderr)
            self.assertIn("no checkpoint_NNNNNN.ckpt", r.stderr)


class RestartAfterKills(unittest.TestCase):
    """SIGKILL at random moments (also inside checkpoint writes): the folder stays readable and
    the newest complete checkpoint always continues the run to the uninterrupted result."""

    KILLS = 24

    def test_random_kills(self):
        overrides = ["time.end=0.04", "output.every=9", "output.checkpoint_every=1"]
        rng = random.Random(20261202)
        with tempfile.TemporaryDirectory() as tmp:
            full, out = os.path.join(tmp, "full"), os.path.join(tmp, "out")
            t0 = time.time()
            r = shellflow("run", PISTON, "-o", full, "--no-plot", *sets(overrides))
            self.assertEqual(r.returncode, 0, r.stderr)
            duration = time.time() - t0
            kills = in_write = 0
            while kills < self.KILLS:
                restart = os.path.isdir(out) and any(n.endswith(".ckpt") for n in os.listdir(out))
                args = ["--restart", out] if restart else ["-o", out]
                p = subprocess.Popen([EXE, "run", PISTON, *args, "--no-plot", *sets(overrides)],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
                time.sleep(rng.uniform(0.05, 0.25) * max(duration, 1.0))
                p.kill()
                _, err = p.communicate(timeout=60)
                # Finished before the kill (a restart from the last step's checkpoint only writes the
                # end-of-run files): start over.
                if p.returncode == 0:
                    for name in os.listdir(out):
                        os.remove(os.path.join(out, name))
                    continue
                self.assertEqual(p.returncode, -signal.SIGKILL, err)
                kills += 1
                if not os.path.isdir(out):
                    continue
                in_write += any(n.startswith("checkpoint_") and n.endswith(".tmp") for n in os.listdir(out))
                if os.path.exists(os.path.join(out, "probes.csv")):
                    assert_readable(self, out)
            r = shellflow("run", PISTON, "--restart", out, "--no-plot", *sets(overrides))
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(outputs(full), outputs(out))
            self.assertFalse([n for n in os.listdir(out) if n.endswith(".tmp")])
            print(f"{kills} kills, {in_write} inside a checkpoint write", flush=True)
            self.assertGreater(in_write, 0, "no kill landed inside a checkpoint write")


if __name__ == "__main__":
    unittest.main()
