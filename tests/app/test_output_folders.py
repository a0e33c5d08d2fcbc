#!/usr/bin/env python3
"""Output folders a hostile case bundle or a careless user cannot turn against the user (issue 24,
docs/output.md "What a run may write"): no write through a symbolic link, one process per folder,
no run into the root or home folder or into a folder of someone else's files, a mesh input
inside the output folder, study points that never share a folder.

usage: SHELLFLOW_EXE=build/ci/app/shellflow python3 tests/app/test_output_folders.py -v
"""
import os
import subprocess
import tempfile
import time
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXE = os.path.abspath(os.environ.get("SHELLFLOW_EXE", os.path.join(ROOT, "build", "release", "app", "shellflow")))
PISTON = os.path.join(ROOT, "cases", "panel_flutter", "clamped_clamped_piston.yaml")
SHORT = ["--set", "time.end=0.002", "--set", "output.checkpoint_every=10"]


def shellflow(*args, env=None, **kw):
    return subprocess.run([EXE, *args], capture_output=True, text=True, timeout=300,
                          env={**os.environ, **(env or {})}, **kw)


def error_line(test, r):
    test.assertEqual(r.returncode, 1, r.stderr)
    errors = [line for line in r.stderr.splitlines() if line.startswith("shellflow: error: ")]
    test.assertEqual(len(errors), 1, r.stderr)
    return errors[0]


class SymlinkedOutputs(unittest.TestCase):
    """A link named like any file a run writes: the run refuses to start and the target is untouched."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.out = os.path.join(cls.tmp.name, "results")
        r = shellflow("run", PISTON, "-o", cls.out, *SHORT)
        assert r.returncode == 0, r.stderr

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def setUp(self):
        self.victim = os.path.join(self.tmp.name, "victim.txt")
        with open(self.victim, "w") as f:
            f.write("keep me\n")

    def planted(self, name, command=("run", PISTON, "-o")):
        path = os.path.join(self.out, name)
        if os.path.lexists(path):
            os.remove(path)
        os.symlink(self.victim, path)
        try:
            r = shellflow(*command, self.out, *(SHORT if command[0] == "run" else []))
        finally:
            os.remove(path)
            if name == ".shellflow.lock":
                open(path, "w").close()  # the folder stays a shellflow output folder
        with open(self.victim) as f:
            self.assertEqual(f.read(), "keep me\n", name)
        return r

    def test_every_output_name(self):
        for name in ("probes.csv", "coupling.csv", "response.json", "shell.pvd", "shell_000000.vtu", "shell.msh",
                     "shell.msh.cache", "probes.png", "mesh_quality.csv", "checkpoint_000010.ckpt.tmp",
                     "shell.pvd.tmp", ".shellflow.lock"):
            with self.subTest(name):
                line = error_line(self, self.planted(name))
                self.assertIn(f"{name}: is a symbolic link (to {self.victim})", line)
                self.assertIn("does not write through links", line)

    def test_flutter_and_mesh_outputs(self):
        for name, command in (("flutter.json", ("flutter", PISTON, "-o")),
                              ("flutter_locus.csv", ("flutter", PISTON, "-o")),
                              ("meshes.json", ("mesh", PISTON, "--no-plot", "-o"))):
            with self.subTest(name):
                self.assertIn(f"{name}: is a symbolic link", error_line(self, self.planted(name, command)))

    def test_a_link_in_a_fresh_bundle_folder(self):
        folder = os.path.join(self.tmp.name, "bundle", "results")
        os.makedirs(folder)
        os.symlink(self.victim, os.path.join(folder, "probes.csv"))
        line = error_line(self, shellflow("run", PISTON, "-o", folder, *SHORT))
        self.assertIn("probes.csv", line)
        with open(self.victim) as f:
            self.assertEqual(f.read(), "keep me\n")


class FoldersThatAreNotARunsOwn(unittest.TestCase):
    def test_root_and_home_are_refused(self):
        with tempfile.TemporaryDirectory() as home:
            for folder, what in (("/", "is the root folder"), (home, "is your home folder")):
                with self.subTest(folder):
                    before = sorted(os.listdir(folder))
                    line = error_line(self, shellflow("run", PISTON, "-o", folder, *SHORT, env={"HOME": home}))
                    self.assertIn(what, line)
                    self.assertIn("give a folder of its own with -o", line)
                    self.assertEqual(sorted(os.listdir(folder)), before)

    def test_a_folder_of_someone_elses_files_is_not_cleaned(self):
        with tempfile.TemporaryDirectory() as folder:
            with open(os.path.join(folder, "response.json"), "w") as f:
                f.write("my own notes\n")
            line = error_line(self, shellflow("run", PISTON, "-o", folder, *SHORT))
            self.assertIn("holds response.json but is not a shellflow output folder (no .shellflow.lock)", line)
            with open(os.path.join(folder, "response.json")) as f:
                self.assertEqual(f.read(), "my own notes\n")

    def test_a_mesh_input_inside_the_output_folder(self):
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "out")
            r = shellflow("mesh", PISTON, "-o", out, "--no-plot")
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(PISTON) as f:
                text = f.read().replace("geo: panel_strip.geo, order: 3", f"msh: {os.path.join(out, 'shell.msh')}")
            case = os.path.join(tmp, "case.yaml")
            with open(case, "w") as f:
                f.write(text)
            with open(os.path.join(out, "shell.msh"), "rb") as f:
                mesh = f.read()
            r = shellflow("run", case, "-o", out, "--no-plot", *SHORT)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(out, "shell.msh"), "rb") as f:
                self.assertEqual(f.read(), mesh)


class OneProcessPerFolder(unittest.TestCase):
    def test_a_second_process_is_refused_with_the_holders_pid(self):
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "out")
            first = subprocess.Popen([EXE, "run", PISTON, "-o", out, "--no-plot", "--set", "time.end=10",
                                      "--set", "output.checkpoint_every=50"],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            try:
                probes = os.path.join(out, "probes.csv")
                deadline = time.monotonic() + 60
                while not (os.path.exists(probes) and os.path.getsize(probes) > 2000):
                    self.assertLess(time.monotonic(), deadline, "the first run wrote no probes")
                    time.sleep(0.05)
                for args in (("run", PISTON, "-o", out, "--no-plot"), ("run", PISTON, "--restart", out, "--no-plot"),
                             ("flutter", PISTON, "-o", out), ("mesh", PISTON, "-o", out, "--no-plot")):
                    with self.subTest(args[0] + " " + args[2]):
                        line = error_line(self, shellflow(*args))
                        self.assertIn(f"another shellflow process (pid {first.pid}) is writing in this output folder",
                                      line)
                        self.assertIn("choose another folder with -o", line)
                self.assertIsNone(first.poll(), "the first run must go on")
            finally:
                first.terminate()
                first.wait(timeout=60)
            # Its lock went with it: the folder continues from its checkpoint.
            r = shellflow("run", PISTON, "--restart", out, "--no-plot", "--set", "time.end=10", "--stop-after", "2")
            self.assertEqual(r.returncode, 75, r.stderr)


if __name__ == "__main__":
    unittest.main()
