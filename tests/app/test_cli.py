#!/usr/bin/env python3
"""Command-line tests of `shellflow` (run by CTest from the source tree).

The executable comes from $SHELLFLOW_EXE. Case variants with errors are written to a
temporary directory, with their mesh paths made absolute.
"""
import csv
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXE = os.environ.get("SHELLFLOW_EXE", os.path.join(ROOT, "build", "release", "app", "shellflow"))
PANEL = os.path.join(ROOT, "cases", "panel_flutter", "clamped_clamped.yaml")
PANEL_COARSE = os.path.join(ROOT, "cases", "panel_flutter", "clamped_clamped_coarse.yaml")


def shellflow(*args):
    return subprocess.run([EXE, *args], capture_output=True, text=True, timeout=600)


def panel_case_text(path=PANEL):
    """The case text with its mesh files made absolute (so that it runs from anywhere)."""
    with open(path) as f:
        text = f.read()
    folder = os.path.dirname(path)
    return re.sub(r"geo: ([\w./]+\.geo)", lambda m: "geo: " + os.path.normpath(os.path.join(folder, m.group(1))), text)


def run_case(test, outdir, folder, name):
    """`shellflow run cases/FOLDER/NAME -o OUTDIR`; asserts success, returns the process and
    the rows of probes.csv (header first)."""
    r = shellflow("run", os.path.join(ROOT, "cases", folder, name), "-o", outdir, "--no-plot")
    test.assertEqual(r.returncode, 0, r.stderr)
    with open(os.path.join(outdir, "probes.csv"), newline="") as f:
        return r, list(csv.reader(f))


def read_vtu_point_arrays(path):
    """Point-data arrays of a .vtu written by shellflow (raw appended Float64 with a UInt64
    byte count before every array): {name: list of tuples}."""
    import struct
    with open(path, "rb") as f:
        data = f.read()
    marker = data.index(b'<AppendedData encoding="raw">')
    start = data.index(b"_", marker) + 1
    header = data[:marker].decode()
    arrays = {}
    for m in re.finditer(r'<DataArray type="Float64" Name="(\w+)" NumberOfComponents="(\d+)" '
                         r'format="appended" offset="(\d+)"', header.split("<Cells>")[0]):
        name, components, offset = m.group(1), int(m.group(2)), int(m.group(3))
        (size,) = struct.unpack_from("<Q", data, start + offset)
        values = struct.unpack_from(f"<{size // 8}d", data, start + offset + 8)
        arrays[name] = [values[i:i + components] for i in range(0, len(values), components)]
    return arrays


def line_of(text, needle):
    for number, line in enumerate(text.splitlines(), start=1):
        if needle in line:
            return number
    raise AssertionError(f"'{needle}' not in the case text")


class CheckCommand(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def write_case(self, text):
        path = os.path.join(self.tmp.name, "bad.yaml")
        with open(path, "w") as f:
            f.write(text)
        return path

    def assert_one_line_error(self, text, key, line_needle):
        path = self.write_case(text)
        r = shellflow("check", path)
        self.assertNotEqual(r.returncode, 0, r.stdout)
        lines = r.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, r.stderr)
        expected = f"{path}:{line_of(text, line_needle)}: {key}"
        self.assertIn(expected, lines[0])
        return lines[0]

    def test_reference_case_is_valid(self):
        r = shellflow("check", PANEL)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("OK", r.stdout)

    def test_misspelled_key(self):
        text = panel_case_text().replace("thickness: 1.35e-3", "thicknes: 1.35e-3")
        message = self.assert_one_line_error(text, "shell.thicknes", "thicknes:")
        self.assertIn("thickness", message)  # the suggestion

    def test_missing_physical_group(self):
        text = panel_case_text().replace("group: leading_edge", "group: leading_egde")
        message = self.assert_one_line_error(text, "shell.supports[0].group", "leading_egde")
        self.assertIn("leading_edge", message)

    def test_negative_thickness(self):
        text = panel_case_text().replace("thickness: 1.35e-3", "thickness: -1.35e-3")
        self.assert_one_line_error(text, "shell.thickness", "thickness:")

    def test_output_directory_is_not_passed_through_a_shell(self):
        # The plot step starts Python with an argument vector: quotes and ; in the output
        # directory are just characters of a file name.
        hostile = os.path.join(self.tmp.name, 'o"; touch INJECTED; echo "')
        r = shellflow("run", os.path.join(ROOT, "cases", "shell", "sze31_end_shear.yaml"), "-o", hostile)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertFalse(os.path.exists("INJECTED"))
        self.assertFalse(os.path.exists(os.path.join(self.tmp.name, "INJECTED")))
        self.assertTrue(os.path.getsize(os.path.join(hostile, "probes.png")) > 1000)

    def test_missing_case_file_is_a_usage_error(self):
        r = shellflow("check", os.path.join(self.tmp.name, "none.yaml"))
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("none.yaml", r.stderr)

    def test_version_and_help(self):
        r = shellflow("--version")
        self.assertEqual(r.returncode, 0)
        self.assertRegex(r.stdout, r"shellflow \d+\.\d+\.\d+")
        for sub in ("run", "mesh", "check"):
            r = shellflow(sub, "--help")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("case", r.stdout.lower())
        self.assertIn("--json", shellflow("mesh", "--help").stdout)


class MeshAndRunCommands(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.out = os.path.join(cls.tmp.name, "panel")

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_1_mesh_json_reports_the_papers_sizes(self):
        r = shellflow("mesh", PANEL, "-o", self.out, "--json", "--no-plot")
        self.assertEqual(r.returncode, 0, r.stderr)
        report = json.loads(r.stdout)
        expected = {  # (nodes, elements, element type), paper's sizes, +-15 %
            "fluid": ((8600, 8600), (25000, 30000), "tet4"),
            "space": ((1000, 1000), (170, 170), "tet20"),
            "shell": ((244, 244), (40, 40), "tri10"),
        }
        for key, ((n_lo, n_hi), (e_lo, e_hi), etype) in expected.items():
            m = report[key]
            self.assertEqual(m["element_type"], etype)
            self.assertGreaterEqual(m["nodes"], 0.85 * n_lo, key)
            self.assertLessEqual(m["nodes"], 1.15 * n_hi, key)
            self.assertGreaterEqual(m["elements"], 0.85 * e_lo, key)
            self.assertLessEqual(m["elements"], 1.15 * e_hi, key)
            self.assertGreater(m["min_quality"], 0.0, key)
        # panel_strip.geo: a 20 x 1 grid of quads split in two, 40 tri10 with (3 * 20 + 1)(3 * 1 + 1) = 244 nodes.
        self.assertEqual((report["shell"]["nodes"], report["shell"]["elements"]), (244, 40))
        # The wet wall's resolution: 8.8 mm cells in the stream (the paper's), and the
        # streamwise wavelengths 2 pi / k_rms of the clamped-clamped beam's first two modes,
        # k_rms^2 = int phi'^2 / int phi^2, integrated here from the beam's mode shapes.
        wet = report["wet_wall"]
        self.assertAlmostEqual(wet["mach"], 2.3)
        self.assertAlmostEqual(wet["cell_size"], 0.0088, delta=0.03 * 0.0088)  # fluid_slab.geo h_panel
        self.assertEqual([m["mode"] for m in wet["modes"]], [1, 2])
        for m, (beta_l, sigma) in zip(wet["modes"], ((4.730040745, 0.982502215), (7.853204624, 1.000777312))):
            n, value, slope = 20000, 0.0, 0.0
            for i in range(n):
                x = (i + 0.5) / n * beta_l
                value += (math.cosh(x) - math.cos(x) - sigma * (math.sinh(x) - math.sin(x))) ** 2
                slope += (math.sinh(x) + math.sin(x) - sigma * (math.cosh(x) - math.cos(x))) ** 2
            wavelength = 2 * math.pi * 0.5 / beta_l * math.sqrt(value / slope)
            self.assertAlmostEqual(m["wavelength"] / wavelength, 1.0, delta=2e-3)
            self.assertAlmostEqual(m["front_wavelength"], m["wavelength"] / 2.3)
            self.assertAlmostEqual(m["cells"], m["front_wavelength"] / wet["cell_size"])

    def test_2_mesh_files_open_in_meshio(self):
        import meshio

        with open(os.path.join(self.out, "meshes.json")) as f:
            report = json.load(f)
        for key in ("fluid", "space", "shell"):
            for ext in (".vtu", ".msh"):
                m = meshio.read(os.path.join(self.out, key + ext))
                cells = sum(len(c.data) for c in m.cells if c.dim == (2 if key == "shell" else 3))
                self.assertEqual(cells, report[key]["elements"], key + ext)
                self.assertEqual(len(m.points), report[key]["nodes"], key + ext)

    def test_3_run_writes_fields_probes_and_plots(self):
        # The coarse variant of the default case (the full one runs for minutes).
        r = shellflow("run", PANEL_COARSE, "-o", self.out)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(self.out, "probes.csv"), newline="") as f:
            rows = list(csv.reader(f))
        self.assertEqual(rows[0], ["time", "w_x0600", "w_x0625", "p_panel_mean"])
        # t = 0: the panel at rest, the flow's own state (p from its conservative variables):
        # the case's free-stream p = 28 kPa.
        self.assertEqual([float(v) for v in rows[1][:3]], [0.0, 0.0, 0.0])
        self.assertAlmostEqual(float(rows[1][3]), 28000.0, delta=1e-9 * 28000.0)
        self.assertEqual(len(rows), 1 + 1 + 100)  # header, t = 0, 100 shell steps
        for key in ("fluid", "space", "shell"):
            self.assertTrue(os.path.exists(os.path.join(self.out, key + ".pvd")))
        for png in ("probes.png", "flutter.png", "flutter_growth.png", "mesh_quality.png"):
            self.assertTrue(os.path.getsize(os.path.join(self.out, png)) > 1000, png)
        # The cavity pressure dips by 0.1 % until 4 ms: the panel is pulled into the cavity.
        self.assertLess(float(rows[40][1]), 0.0)


class CoupledRuns(unittest.TestCase):
    """Coupled shell + flow runs (cases/panel_flutter, cases/mesh_motion_tests)."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def write_case(self, text, name="case.yaml"):
        path = os.path.join(self.tmp.name, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def test_piston_theory_flutter_grows_and_writes_the_coupling_log(self):
        text = panel_case_text(os.path.join(ROOT, "cases", "panel_flutter", "clamped_sliding_piston.yaml"))
        text = text.replace("end: 0.14", "end: 0.03")
        out = os.path.join(self.tmp.name, "out")
        r = shellflow("run", self.write_case(text), "-o", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("coupled run: 300 shell steps", r.stderr)
        with open(os.path.join(out, "coupling.csv"), newline="") as f:
            rows = list(csv.reader(f))
        self.assertEqual(rows[0][:5], ["time", "newton_iterations", "coupling_iterations", "coupling_residual", "substeps"])
        self.assertEqual(len(rows), 301)
        with open(os.path.join(out, "probes.csv"), newline="") as f:
            w = [abs(float(row[1])) for row in list(csv.reader(f))[1:]]
        # Above the flutter boundary the oscillation grows: later peaks are larger (the linear
        # eigenvalue's 51.6 1/s gives e^(51.6 * 0.01) = 1.68 per 10 ms, docs/coupling.md).
        self.assertGreater(max(w[200:]), 1.5 * max(w[100:200]))
        self.assertTrue(os.path.getsize(os.path.join(out, "flutter_growth.png")) > 1000)
        self.assertTrue(os.path.exists(os.path.join(out, "response.json")))  # every coupled run

    def test_viscous_flutter_coarse_passes_the_shear_to_the_shell(self):
        # cases/viscous_coupling/flutter_viscous_coarse.yaml (the CI variant, 10 ms): no-slip
        # panel and plate in viscous air; the panel takes the gas's shear with its pressure.
        out = os.path.join(self.tmp.name, "out")
        r = shellflow("run", os.path.join(ROOT, "cases", "viscous_coupling", "flutter_viscous_coarse.yaml"), "-o", out,
                      "--no-plot")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("coupled run: 100 shell steps", r.stderr)
        with open(os.path.join(out, "coupling.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 100)
        # Along the flow (x) the force on the flat panel is the shear alone: the gas drags the
        # panel downstream, and the shell gets what the fluid gives (the force balance).
        last = rows[-1]
        shell_x, fluid_x = float(last["shell_force_x"]), float(last["fluid_force_x"])
        self.assertGreater(fluid_x, 0.0)
        self.assertLess(abs(shell_x - fluid_x), 0.05 * fluid_x)
        self.assertLess(max(float(row["force_balance"]) for row in rows[10:]), 1e-3)

    def test_strong_coupling_needs_the_coupling_iterations(self):
        # cases/strong_coupling: rho c dt / (rho_s h) = 2 (docs/coupling.md, "Implicit coupling").
        case = os.path.join(ROOT, "cases", "strong_coupling", "thin_sheet_dense_gas.yaml")
        out = os.path.join(self.tmp.name, "iqn")
        r = shellflow("run", case, "-o", out, "--no-plot", "--set", "time.end=0.01")
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(out, "coupling.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 100)
        iterations = [int(float(row["coupling_iterations"])) for row in rows]
        self.assertTrue(all(2 <= k <= 30 for k in iterations), iterations)
        self.assertTrue(all(float(row["coupling_residual"]) <= 1e-6 for row in rows))
        with open(os.path.join(out, "probes.csv"), newline="") as f:
            w = [abs(float(row[1])) for row in list(csv.reader(f))[1:]]
        self.assertLess(max(w), 1e-5)  # the 1e-6 dip moves the sheet by micrometres
        # The loose scheme blows up: one clear line naming the step and what to change.
        loose = os.path.join(self.tmp.name, "loose")
        r = shellflow("run", case, "-o", loose, "--no-plot", "--set", "coupling.iterations=1",
                      "--set", "coupling.acceleration=none")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("warning: " + case + ": the added-mass ratio rho_inf a_inf dt / (rho_s h) = 2.01", r.stderr)
        last = r.stderr.strip().splitlines()[-1]
        self.assertRegex(last, r"^shellflow: error: t = [0-9.]+ s: the loads from the flow missed the predicted ones")
        self.assertIn("blew up", last)
        self.assertIn("coupling.acceleration: iqn_ils", last)
        self.assertRegex(last, r"\(step [0-9]+\); the last valid state")
        # The plain fixed point converges too slowly for 10 iterations.
        plain = os.path.join(self.tmp.name, "plain")
        r = shellflow("run", case, "-o", plain, "--no-plot", "--set", "coupling.iterations=10",
                      "--set", "coupling.acceleration=none")
        self.assertNotEqual(r.returncode, 0)
        last = r.stderr.strip().splitlines()[-1]
        self.assertRegex(last, r"^shellflow: error: t = 0.0001 s: the coupling iterations did not converge in 10 "
                               r"iterations \(relative load residual [0-9.e+-]+ > coupling.tolerance 1.000e-06\)")
        self.assertIn("(step 1)", last)

    def piston_case_with_response(self, response, end="0.08"):
        text = panel_case_text(os.path.join(ROOT, "cases", "panel_flutter", "clamped_sliding_piston.yaml"))
        text = text.replace("end: 0.14", "end: " + end)
        text = re.sub(r"\n  # growth rate[^\n]*\n  response: [^\n]*", "", text)  # the case's own
        return text.replace("\n  wet_normal:", "\n  response: " + response + "\n  wet_normal:")

    def test_piston_theory_flutter_writes_the_response_analysis(self):
        text = self.piston_case_with_response("{ probe: w_x0625, window: [0.02, 0.08], lco_cycles: 3 }")
        out = os.path.join(self.tmp.name, "out")
        r = shellflow("run", self.write_case(text), "-o", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("response of w_x0625 on [0.02, 0.08] s", r.stderr)
        with open(os.path.join(out, "response.json")) as f:
            resp = json.load(f)
        self.assertEqual(set(resp), {"probe", "window", "frequency_hz", "growth_rate", "growth_rate_error", "extrema",
                                     "last_amplitude", "envelope_change", "saturated", "lco", "peak_times",
                                     "peak_values"})
        self.assertEqual(resp["probe"], "w_x0625")
        self.assertEqual(resp["window"], [0.02, 0.08])
        self.assertEqual(len(resp["peak_times"]), resp["extrema"])
        # Still growing at 0.08 s: no limit cycle.
        self.assertFalse(resp["saturated"])
        self.assertIsNone(resp["lco"])
        self.assertGreater(resp["envelope_change"], 0.5)

        # An independent fit from probes.csv: the largest |w| sample of each half-cycle in the
        # window (the first and last, cut by the window, dropped), log|w| against t by least
        # squares; the frequency from the first and last zero crossings (linear interpolation).
        with open(os.path.join(out, "probes.csv"), newline="") as f:
            rows = list(csv.reader(f))
        column = rows[0].index("w_x0625")
        samples = [(float(row[0]), float(row[column])) for row in rows[1:]]
        samples = [(t, w) for t, w in samples if 0.02 <= t <= 0.08]
        halves = []
        for t, w in samples:
            if halves and (w > 0) == (halves[-1][1] > 0):
                if abs(w) > abs(halves[-1][1]):
                    halves[-1] = (t, w)
            else:
                halves.append((t, w))
        peaks = halves[1:-1]
        n = len(peaks)
        mt = sum(t for t, _ in peaks) / n
        my = sum(math.log(abs(w)) for _, w in peaks) / n
        sigma = sum((t - mt) * (math.log(abs(w)) - my) for t, w in peaks) / sum((t - mt) ** 2 for t, _ in peaks)
        crossings = [t0 + (t1 - t0) * w0 / (w0 - w1)
                     for (t0, w0), (t1, w1) in zip(samples, samples[1:]) if w0 * w1 < 0]
        frequency = (len(crossings) - 1) / (2 * (crossings[-1] - crossings[0]))
        self.assertEqual(resp["extrema"], n)
        self.assertGreater(sigma, 40)  # flutter (the linear eigenvalue is 51.6 1/s)
        self.assertLess(abs(resp["growth_rate"] / sigma - 1), 0.01, (resp["growth_rate"], sigma))
        self.assertLess(abs(resp["frequency_hz"] / frequency - 1), 0.002, (resp["frequency_hz"], frequency))
        self.assertGreater(resp["growth_rate_error"], 0)
        self.assertLess(resp["growth_rate_error"], 0.05 * sigma)
        self.assertTrue(os.path.getsize(os.path.join(out, "flutter.png")) > 1000)

    def test_an_unknown_response_probe_names_the_key_and_the_probes(self):
        self.assert_run_error(self.piston_case_with_response("{ probe: w_x06 }", end="0.001"),
                              "coupling.response.probe", "'w_x06'", "w_x0600, w_x0625")

    def test_a_response_window_must_increase_and_lco_cycles_be_positive(self):
        self.assert_run_error(self.piston_case_with_response("{ window: [0.08, 0.02] }"),
                              "coupling.response.window", "t_start < t_end")
        self.assert_run_error(self.piston_case_with_response("{ lco_cycles: 0 }"), "coupling.response.lco_cycles")

    def test_mesh_motion_test_follows_the_shell(self):
        out = os.path.join(self.tmp.name, "mm")
        r, rows = run_case(self, out, "mesh_motion_tests", "up_5000.yaml")
        self.assertEqual(len(rows), 1 + 1 + 12)  # header, t = 0, 12 shell steps
        self.assertGreater(float(rows[-5][1]), 0.01)  # the panel bulges up by centimetres
        with open(os.path.join(out, "mesh_quality.csv"), newline="") as f:
            q = list(csv.reader(f))
        self.assertEqual(q[0][1:], ["fluid_min_quality", "fluid_mean_quality", "fluid_min_quality_ratio",
                                    "fluid_inverted", "space_min_quality", "space_min_relative_jacobian"])
        self.assertTrue(all(float(row[4]) == 0 for row in q[1:]))
        for key in ("fluid", "space", "shell"):
            self.assertTrue(os.path.exists(os.path.join(out, key + ".pvd")), key)

    def assert_run_error(self, text, *needles):
        out = os.path.join(self.tmp.name, "err")
        r = shellflow("run", self.write_case(text), "-o", out, "--no-plot")
        self.assertNotEqual(r.returncode, 0, r.stderr)
        lines = r.stderr.strip().splitlines()
        for needle in needles:
            self.assertIn(needle, lines[-1])
        return lines[-1]

    def test_meshes_that_do_not_share_the_wet_surface_are_refused(self):
        # The shell 1 mm above the fluid's panel wall.
        with open(os.path.join(ROOT, "cases", "panel_flutter", "panel_strip.geo")) as f:
            geo = f.read().replace(", 0, ", ", 0.001, ")
        lifted = self.write_case(geo, "lifted_strip.geo")
        text = panel_case_text(PANEL_COARSE)
        text = re.sub(r"shell: \{ geo: [^,]+,", "shell: { geo: " + lifted + ",", text)
        text = text.replace(", 0.0, 0.0125]", ", 0.001, 0.0125]")  # the shell probes on the lifted shell
        line = self.assert_run_error(text, "fluid wall nodes -> shell", "largest gap is 1.000e-03 m", "max_gap")
        self.assertIn("Gmsh node tag", line)

    def test_a_wet_group_the_motion_does_not_move_is_refused(self):
        text = panel_case_text(PANEL_COARSE).replace("fluid_group: panel", "fluid_group: far_field")
        self.assert_run_error(text, "coupling.fluid_group 'far_field' must be one of motion.interface_groups")

    def test_a_missing_coupling_group_names_the_group(self):
        text = panel_case_text(PANEL_COARSE).replace("fluid_group: panel", "fluid_group: panell")
        self.assert_run_error(text, "coupling.fluid_group", "panell", "panel")

    def test_too_few_fixed_substeps_name_the_time_and_the_count_needed(self):
        text = panel_case_text(PANEL_COARSE).replace("substeps: auto", "substeps: 3")
        self.assert_run_error(text, "t = 0 s", "needs at least", "coupling.substeps")

    def test_an_inverting_coupled_step_stops_after_writing_the_last_valid_state(self):
        path = os.path.join(ROOT, "cases", "mesh_motion_tests", "antisymmetric_15000.yaml")
        text = panel_case_text(path).replace("pressure: -15000", "pressure: -900000").replace(
            "pressure: 15000", "pressure: 900000")
        # Regression pin (antisymmetric_15000 at +-900 kPa on the flutter meshes, measured 2026-12-01): the
        # fluid mesh inverts at step 2, the last valid state is t = 0.001 s; not a reference.
        line = self.assert_run_error(text, "inverts fluid element", "(step 2)", "the last valid state (t = 0.001 s)")
        self.assertRegex(line, r"t = 0\.00\d+ s: the mesh motion inverts")
        out = os.path.join(self.tmp.name, "err")
        import xml.etree.ElementTree as ET
        for key in ("fluid", "space", "shell"):
            files = [d.get("file") for d in ET.parse(os.path.join(out, key + ".pvd")).iter("DataSet")]
            self.assertTrue(files, key)
            for f in files:
                self.assertIn("displacement", read_vtu_point_arrays(os.path.join(out, f)), f)

    def test_piston_theory_needs_the_wet_side(self):
        text = panel_case_text(os.path.join(ROOT, "cases", "panel_flutter", "clamped_clamped_piston.yaml"))
        text = re.sub(r"\n  wet_normal:.*", "", text)
        self.assert_run_error(text, "coupling", "wet_normal")

    def test_every_coupled_case_is_valid(self):
        for folder, names in (("panel_flutter", ("clamped_clamped", "clamped_sliding", "clamped_clamped_piston",
                                                 "clamped_sliding_piston", "clamped_sliding_piston_monolithic",
                                                 "clamped_clamped_coarse")),
                              ("mesh_motion_tests", ("up_5000", "down_5000", "antisymmetric_15000")),
                              ("viscous_coupling", ("couette_strip", "boundary_layer_panel", "flutter_viscous",
                                                    "flutter_viscous_coarse"))):
            for name in names:
                r = shellflow("check", os.path.join(ROOT, "cases", folder, name + ".yaml"))
                self.assertEqual(r.returncode, 0, name + ": " + r.stderr)


class ShellRuns(unittest.TestCase):
    """Static shell benchmarks run from their case files (cases/shell)."""

    def test_sze31_end_shear_meets_the_elastica_at_every_level(self):
        with tempfile.TemporaryDirectory() as tmp:
            r, rows = run_case(self, tmp, "shell", "sze31_end_shear.yaml")
            self.assertEqual(rows[0], ["time", "tip_u", "tip_w"])
            self.assertEqual(len(rows), 22)  # t = 0 and 20 load levels
            check = subprocess.run(
                [sys.executable, os.path.join(ROOT, "tools", "plot_load_displacement.py"),
                 os.path.join(tmp, "probes.csv"),
                 os.path.join(ROOT, "cases", "shell", "reference_sze31.csv"),
                 "-o", os.path.join(tmp, "sze31.png"), "--check", "0.002"],
                capture_output=True, text=True)
            self.assertEqual(check.returncode, 0, check.stdout + check.stderr)
            self.assertTrue(os.path.exists(os.path.join(tmp, "shell.pvd")))


    def test_oblique_strip_with_hard_supports_and_symmetry_planes(self):
        # Supports along non-axis directions, hard simple support, surface traction and the
        # stress output: plate-strip bending on an oblique plane (the case file's header).
        with tempfile.TemporaryDirectory() as tmp:
            r, rows = run_case(self, tmp, "shell", "oblique_strip_hard_support.yaml")
            w = float(rows[-1][1])
            # Midspan, bending and shear: w = 5 p L^4 / (384 D) + p L^2 / (8 k G h) = 1.42227e-6 m.
            self.assertLess(abs(w / 1.42227e-6 - 1.0), 2e-3, w)
            fields = read_vtu_point_arrays(os.path.join(tmp, "shell_000001.vtu"))
            for side in ("bottom", "middle", "top"):
                self.assertIn(f"cauchy_stress_{side}", fields)
                self.assertEqual(len(fields[f"cauchy_stress_{side}"][0]), 9)
            # Largest face stress: at midspan, 75 sqrt(1 - nu + nu^2) = 66.66 Pa von Mises.
            # The cubic elements' curvature is linear in each element while M is quadratic:
            # the nodal value at midspan is high by O(element length^2), measured 0.84 % with
            # 8 elements along and 0.14 % with the case's 16.
            top = max(v[0] for v in fields["von_mises_top"])
            bottom = max(v[0] for v in fields["von_mises_bottom"])
            middle = max(v[0] for v in fields["von_mises_middle"])
            expected = 75.0 * math.sqrt(1.0 - 0.3 + 0.09)
            self.assertLess(abs(top / expected - 1.0), 3e-3, top)
            self.assertLess(abs(bottom / expected - 1.0), 3e-3, bottom)
            # Mid-surface: only the transverse shear at the supports, sqrt(3) 1.5 V / h = 1.3 Pa.
            self.assertLess(middle, 1.5)

    def test_prescribed_rotation_turns_the_cantilever_rigidly(self):
        with tempfile.TemporaryDirectory() as tmp:
            r, rows = run_case(self, tmp, "shell", "cantilever_prescribed_rotation.yaml")
            rows = [[float(x) for x in row] for row in rows[1:]]
            self.assertEqual(len(rows), 6)
            for lam, u, w in rows:
                angle = 0.5 * lam
                self.assertAlmostEqual(u, 10.0 * math.cos(angle) - 10.0, delta=1e-9)
                self.assertAlmostEqual(w, -10.0 * math.sin(angle), delta=1e-9)

    def test_hinged_roof_snaps_through_with_arc_length(self):
        with tempfile.TemporaryDirectory() as tmp:
            case = os.path.join(ROOT, "cases", "shell", "hinged_roof_snap.yaml")
            r = shellflow("run", case, "-o", tmp, "--no-plot")
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(tmp, "probes.csv"), newline="") as f:
                rows = [(float(a), float(b)) for a, b in list(csv.reader(f))[1:]]
            load = [lam for lam, _ in rows]
            peak = max(range(len(load)), key=lambda i: load[i] if i < len(load) // 2 else -1)
            valley = min(load[peak:])
            # Limit load P = 1000 lambda = 2216.6 on this mesh (the path samples it from below);
            # the load drops to lambda = 0.509 during the snap and rises past 2.5 again.
            # Regression pin (4 x 4 cubic quarter mesh, arc length, measured 2026-11-22): limit lambda 2.2166
            # (displacement control on this mesh, docs/shell.md), minimum 0.509; not a reference — the
            # literature's limit load is not confirmed here (docs/shell.md), 8 x 8 gives 2.2159.
            self.assertGreater(load[peak], 2.18)
            self.assertLess(load[peak], 2.2167)
            self.assertLess(abs(valley - 0.509), 0.02)
            self.assertGreaterEqual(load[-1], 2.5)
            deflection = [-w for _, w in rows]
            self.assertTrue(all(b > a for a, b in zip(deflection, deflection[1:])))


class FlowRuns(unittest.TestCase):
    """Flow cases run from their case files (cases/fluid)."""

    def test_sod_plateau_pressure_and_density(self):
        with tempfile.TemporaryDirectory() as tmp:
            r = shellflow("run", os.path.join(ROOT, "cases", "fluid", "sod.yaml"), "-o", tmp,
                          "--no-plot")
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(tmp, "probes.csv"), newline="") as f:
                rows = list(csv.reader(f))
            self.assertEqual(rows[0], ["time", "rho_x0.6", "p_x0.6"])
            t, rho, p = (float(v) for v in rows[-1])
            self.assertAlmostEqual(t, 0.2, places=12)
            # x = 0.6 lies between the rarefaction tail (0.486) and the contact (0.685).
            # Exact Riemann solution (cases/fluid/sod.yaml): p* = 0.3031301781, rho*_L = 0.4263194282.
            self.assertLess(abs(p - 0.3031301781) / 0.3031301781, 0.01)
            self.assertLess(abs(rho - 0.4263194282) / 0.4263194282, 0.02)
            import meshio

            m = meshio.read(os.path.join(tmp, "fluid_000000.vtu"))
            for name in ("density", "velocity", "pressure", "mach", "temperature"):
                self.assertIn(name, m.point_data)


    def test_lax_plateau_between_contact_and_shock(self):
        with tempfile.TemporaryDirectory() as tmp:
            r = shellflow("run", os.path.join(ROOT, "cases", "fluid", "lax.yaml"), "-o", tmp,
                          "--no-plot")
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(tmp, "probes.csv"), newline="") as f:
                rows = list(csv.reader(f))
            t, rho, p = (float(v) for v in rows[-1])
            self.assertAlmostEqual(t, 0.14, places=12)
            # x = 0.8 lies between the contact (0.714) and the shock (0.847).
            # Exact Riemann solution (cases/fluid/lax.yaml): p* = 2.4660979192, rho*_R = 1.3040845320.
            self.assertLess(abs(p - 2.4660979192) / 2.4660979192, 0.01)
            self.assertLess(abs(rho - 1.3040845320) / 1.3040845320, 0.02)


class SteadyFlowRuns(unittest.TestCase):
    """Steady flow by local time stepping from a case file, stopped by residual_drop."""

    def test_ramp_reaches_the_oblique_shock_pressure_and_stops_on_the_residual(self):
        with tempfile.TemporaryDirectory() as tmp:
            case = os.path.join(ROOT, "cases", "fluid", "ramp_15deg.yaml")
            r = shellflow("run", case, "-o", tmp, "--no-plot")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertNotIn("did not drop", r.stdout + r.stderr)
            with open(os.path.join(tmp, "probes.csv"), newline="") as f:
                rows = list(csv.reader(f))
            self.assertLess(len(rows) - 2, 3000)  # stopped by residual_drop, not by steps
            # Wall pressure ratio behind the shock: theta-beta-M 2.4675 (1.5 % in the issue).
            ratio = float(rows[-1][2]) / (1.0 / 1.4)
            self.assertLess(abs(ratio / 2.4675 - 1.0), 0.015, ratio)


class MovingMeshFlowRuns(unittest.TestCase):
    """Flow on meshes moved by a prescribed `fluid.mesh_motion` (cases/fluid)."""

    def run_case(self, name):
        tmp = tempfile.TemporaryDirectory()
        self.addCleanup(tmp.cleanup)
        r = shellflow("run", os.path.join(ROOT, "cases", "fluid", name + ".yaml"), "-o", tmp.name,
                      "--no-plot")
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(tmp.name, "probes.csv"), newline="") as f:
            rows = list(csv.reader(f))
        header = rows[0]
        return tmp.name, {k: [float(row[i]) for row in rows[1:]] for i, k in enumerate(header)}

    def test_free_stream_stays_exact_on_a_deforming_mesh(self):
        _, probes = self.run_case("freestream_deforming")
        self.assertGreater(len(probes["time"]), 100)
        for lo, hi in (("rho_min", "rho_max"), ("p_min", "p_max")):
            for a, b in zip(probes[lo], probes[hi]):
                self.assertLessEqual(b - a, 1e-12 * abs(b), (lo, hi))
        self.assertAlmostEqual(probes["rho_max"][-1], 1.0, delta=1e-12)

    def test_piston_face_pressure_matches_the_exact_shock(self):
        _, probes = self.run_case("piston")
        t, p = probes["time"], probes["p_piston"]
        integral = duration = 0.0
        for i in range(1, len(t)):
            if t[i] > 0.3:
                integral += (t[i] - t[i - 1]) * p[i]
                duration += t[i] - t[i - 1]
        # Exact piston-driven shock (cases/fluid/piston.yaml): face pressure 1.14865177.
        self.assertLess(abs(integral / duration / 1.14865177 - 1.0), 0.005)

    def test_stationary_contact_stays_on_an_oscillating_mesh(self):
        out, probes = self.run_case("contact_oscillating")
        self.assertAlmostEqual(probes["time"][-1], 1.0, places=12)
        # u = 0 and p = 1 exactly in the exact solution; the discrete errors are O(h^2).
        self.assertLess(max(probes["u_max"]), 0.01)
        self.assertLess(max(abs(v - 1.0) for v in probes["p_min"] + probes["p_max"]), 0.01)
        # The nodes are back at X at t = 1; the profile stays where it was.
        rho0 = 1 + 0.5 * math.exp(-((0.6 - 0.5) / 0.1) ** 2)
        self.assertLess(abs(probes["rho_x0.6"][-1] - rho0) / 0.5, 0.02)
        self.assertTrue(os.path.exists(os.path.join(out, "fluid.pvd")))

    def test_entropy_wave_is_advected_through_the_moving_mesh(self):
        _, probes = self.run_case("entropy_wave")
        # A point probe follows the mesh point it was located at: here x(t) = 0.5 + 0.05
        # sin(2 pi t / 0.5). Exact rho = 1 + 0.2 sin(2 pi (x - 2 t)); the inflow has swept the
        # tube once the wave has travelled 0.6.
        worst = 0.0
        for t, rho in zip(probes["time"], probes["rho_x0.5"]):
            if t > 0.3:
                x = 0.5 + 0.05 * math.sin(2 * math.pi * t / 0.5)
                worst = max(worst, abs(rho - 1 - 0.2 * math.sin(2 * math.pi * (x - 2 * t))))
        self.assertLess(worst / 0.2, 0.01)

    def test_sod_on_a_deforming_mesh_keeps_the_plateau(self):
        _, probes = self.run_case("sod_moving_mesh")
        self.assertAlmostEqual(probes["time"][-1], 0.2, places=12)
        # The nodes are back at X at t = 0.2: sod.yaml's exact Riemann plateau, p* and rho*_L.
        self.assertLess(abs(probes["p_x0.6"][-1] - 0.3031301781) / 0.3031301781, 0.01)
        self.assertLess(abs(probes["rho_x0.6"][-1] - 0.4263194282) / 0.4263194282, 0.02)


class MotionRuns(unittest.TestCase):
    """Prescribed panel motion moving the panel fluid mesh (cases/motion)."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def read_quality(self, out):
        with open(os.path.join(out, "motion_quality.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        return rows

    def test_single_mode_to_twelve_centimetres_stays_valid(self):
        out = os.path.join(self.tmp.name, "up")
        case = os.path.join(ROOT, "cases", "motion", "panel_single_mode.yaml")
        r = shellflow("run", case, "-o", out, "--no-plot")
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = self.read_quality(out)
        self.assertEqual(len(rows), 21)
        self.assertAlmostEqual(float(rows[-1]["A1"]), 0.12)
        self.assertTrue(all(float(row["fluid_inverted"]) == 0 for row in rows))
        self.assertTrue(all(float(row["fluid_min_quality"]) > 0 for row in rows))
        # The quality falls monotonically with the amplitude.
        q = [float(row["fluid_min_quality_ratio"]) for row in rows]
        self.assertTrue(all(b <= a + 1e-12 for a, b in zip(q, q[1:])))
        # The mesh written at the end is the deformed one: the panel nodes moved by
        # 0.12 sin(pi s / L), the largest displacement of the mesh.
        import math

        import numpy

        import meshio

        m = meshio.read(os.path.join(out, "fluid_000020.vtu"))
        u, x = m.point_data["displacement"], m.points - m.point_data["displacement"]
        on_panel = (abs(x[:, 1]) < 1e-12) & (x[:, 0] >= 0.25) & (x[:, 0] <= 0.75)
        expected = 0.12 * abs(numpy.sin(math.pi * (x[on_panel, 0] - 0.25) / 0.5))
        self.assertLess(float(abs(u[on_panel, 1] - expected).max()), 1e-14)
        self.assertLessEqual(float(abs(u).max()), 0.12 + 1e-15)
        with open(os.path.join(out, "probes.csv"), newline="") as f:
            probes = list(csv.reader(f))
        self.assertEqual(probes[0], ["time", "panel_mid_y", "w_mesh_max"])
        self.assertEqual(len(probes), 22)

    def test_an_inverting_motion_stops_after_writing_the_last_valid_state(self):
        out = os.path.join(self.tmp.name, "too_far")
        text = open(os.path.join(ROOT, "cases", "motion", "panel_single_mode.yaml")).read()
        folder = os.path.join(ROOT, "cases", "panel_flutter")
        text = text.replace("../panel_flutter", folder).replace("value: 0.12", "value: 0.3")
        case = os.path.join(self.tmp.name, "too_far.yaml")
        with open(case, "w") as f:
            f.write(text)
        r = shellflow("run", case, "-o", out, "--no-plot")
        self.assertEqual(r.returncode, 4)  # the physics stopped the run (a SolverError)
        self.assertIn("inverts", r.stderr)
        # Regression pin (panel_single_mode ramped to 0.3 m, this fluid and space mesh, measured 2026-11-22):
        # the first inverting step is t = 0.45 s; not a reference.
        self.assertIn("t = 0.45 s", r.stderr)
        self.assertIn("last valid state (t = 0.4 s)", r.stderr)
        import xml.etree.ElementTree as ET

        datasets = ET.parse(os.path.join(out, "fluid.pvd")).getroot().iter("DataSet")
        last = list(datasets)[-1]
        self.assertAlmostEqual(float(last.get("timestep")), 0.4)
        import meshio

        m = meshio.read(os.path.join(out, last.get("file")))
        self.assertTrue((m.cell_data["quality"][0] > 0).all())


class ModalRuns(unittest.TestCase):
    """`shell.analysis.type: modal` on the reference strip (cases/shell/strip_modal.yaml)."""

    CASE = os.path.join(ROOT, "cases", "shell", "strip_modal.yaml")
    # Plate-strip theory, clamped-clamped (shell-references.md): beta_n L = 4.730041, 7.853205,
    # 10.995608, 14.137165.
    REFERENCE_HZ = (31.401, 86.557, 169.687, 280.500)

    @classmethod
    def setUpClass(cls):
        import time
        cls.tmp = tempfile.TemporaryDirectory()
        cls.out = os.path.join(cls.tmp.name, "modal")
        start = time.monotonic()
        cls.result = shellflow("run", cls.CASE, "-o", cls.out, "--no-plot")
        cls.seconds = time.monotonic() - start
        with open(cls.CASE) as f:
            cls.modes = int(re.search(r"\n    modes: (\d+)", f.read()).group(1))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def rows(self):
        with open(os.path.join(self.out, "modes.csv"), newline="") as f:
            return list(csv.DictReader(f))

    def test_bending_frequencies_match_plate_strip_theory(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr)
        rows = self.rows()
        # The 20x1 cubic mesh (244 nodes) is 6e-5, 1.1e-4, 1.8e-4, 2.1e-4 below the
        # Euler-Bernoulli values of modes 1-4 (its discretisation error plus the shear and
        # rotary inertia the plate strip leaves out, both growing with the mode number);
        # 5e-4 is above that and below what a wrong thickness or density of 0.1 % moves.
        for k, reference in enumerate(self.REFERENCE_HZ):
            f = float(rows[k]["frequency_hz"])
            self.assertLess(abs(f / reference - 1.0), 5e-4, (k + 1, f, reference))
        self.assertLess(abs(float(rows[0]["frequency_hz"]) / 31.401 - 1.0), 1e-4, rows[0])
        # Regression pin (20 x 1 cubic strip, measured 2026-12-01): mode 1 at 31.399 Hz in the log table; not a
        # reference — plate-strip theory gives 31.401 Hz.
        self.assertIn("31.39", self.result.stderr)  # the log table
        self.assertLess(self.seconds, 60.0)

    def test_modes_csv_has_the_columns_and_one_row_per_mode(self):
        rows = self.rows()
        self.assertEqual(list(rows[0].keys()), ["mode", "frequency_hz", "angular_frequency", "direction",
                                                "kinetic_x", "kinetic_y", "kinetic_z"])
        self.assertEqual(len(rows), self.modes)
        self.assertEqual([int(r["mode"]) for r in rows], list(range(1, self.modes + 1)))
        f = [float(r["frequency_hz"]) for r in rows]
        self.assertEqual(f, sorted(f))
        for r in rows:
            self.assertAlmostEqual(float(r["angular_frequency"]), 2 * math.pi * float(r["frequency_hz"]),
                                   delta=1e-8 * float(r["angular_frequency"]))
        for r in rows[:4]:  # bending: transverse (y), the directors' rotary inertia < 1e-3
            self.assertEqual(r["direction"], "y", r)
            self.assertGreater(float(r["kinetic_y"]), 0.999, r)
        with open(os.path.join(self.out, "modes.json")) as fj:
            report = json.load(fj)
        self.assertEqual(len(report["frequencies_hz"]), self.modes)
        for a, b in zip(report["frequencies_hz"], f):
            self.assertAlmostEqual(a, b, delta=1e-8 * b)
        self.assertGreaterEqual(report["iterations"], 1)

    def test_mode_shapes_in_the_vtu_and_the_pvd_series(self):
        import xml.etree.ElementTree as ET
        arrays = read_vtu_point_arrays(os.path.join(self.out, "shell_modes.vtu"))
        names = [f"mode_{k:02d}" for k in range(1, self.modes + 1)]
        for name in names:
            self.assertIn(name, arrays)
            self.assertEqual(len(arrays[name]), 244)
            # Scaled to a largest nodal displacement of 1.
            self.assertAlmostEqual(max(math.sqrt(sum(c * c for c in v)) for v in arrays[name]), 1.0, delta=1e-12)
        # Mode 1 is symmetric about midspan, mode 2 antisymmetric: at the quarter points
        # (nodes at x = 0.375 and 0.625, z = 0) w is equal / opposite.
        import meshio
        points = meshio.read(os.path.join(self.out, "shell_modes.vtu")).points
        left = min(range(len(points)), key=lambda i: abs(points[i][0] - 0.375) + abs(points[i][2]))
        right = min(range(len(points)), key=lambda i: abs(points[i][0] - 0.625) + abs(points[i][2]))
        w1, w2 = arrays["mode_01"], arrays["mode_02"]
        self.assertAlmostEqual(w1[left][1], w1[right][1], delta=1e-6)
        self.assertAlmostEqual(w2[left][1], -w2[right][1], delta=1e-6)
        self.assertGreater(abs(w1[left][1]), 0.3)  # the clamped beam's mode 1: 0.543 of its peak there
        files = [(float(d.get("timestep")), d.get("file"))
                 for d in ET.parse(os.path.join(self.out, "modes.pvd")).iter("DataSet")]
        self.assertEqual([t for t, _ in files], [float(k) for k in range(1, self.modes + 1)])
        for k, (_, name) in enumerate(files):
            frame = read_vtu_point_arrays(os.path.join(self.out, name))
            self.assertEqual(frame["displacement"], arrays[names[k]], name)

    def test_free_vibration_case_vibrates_at_the_first_modal_frequency(self):
        # cases/shell/strip_free_vibration.yaml: 1 Pa for 12 ms (two periods of mode 3), then
        # free; w_mid's zero crossings after the release give the first mode's frequency less
        # the trapezoidal rule's period elongation (omega dt)^2 / 12 (8.1e-4 at dt = 0.5 ms).
        # Measured 31.3791 Hz against 31.3736 expected (+1.7e-4: what the higher modes and
        # the linear interpolation of the crossings leave).
        f1 = float(self.rows()[0]["frequency_hz"])
        with tempfile.TemporaryDirectory() as tmp:
            r, rows = run_case(self, tmp, "shell", "strip_free_vibration.yaml")
        samples = [(float(t), float(w)) for t, w in rows[1:]]
        crossings = [ta + (tb - ta) * a / (a - b) for (ta, a), (tb, b) in zip(samples, samples[1:])
                     if ta >= 0.0125 and (a > 0) != (b > 0)]
        self.assertGreaterEqual(len(crossings), 5)
        f = (len(crossings) - 1) / (2.0 * (crossings[-1] - crossings[0]))
        dt = 5.0e-4
        expected = f1 * (1.0 - (2 * math.pi * f1 * dt) ** 2 / 12.0)
        self.assertLess(abs(f / expected - 1.0), 5e-4, (f, expected))
        # Linear range: the peak deflection stays below 2 % of h (membrane stiffening ~ amplitude^2).
        self.assertLess(max(abs(w) for _, w in samples), 0.02 * 1.35e-3)

    def check_error(self, text, key, needle):
        path = os.path.join(self.tmp.name, "bad_modal.yaml")
        with open(path, "w") as f:
            f.write(text)
        r = shellflow("check", path)
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
        lines = r.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, r.stderr)
        self.assertIn(f"{path}:{line_of(text, needle)}: {key}", lines[0])
        return lines[0]

    def test_check_accepts_the_modal_case_and_refuses_bad_keys(self):
        r = shellflow("check", self.CASE)
        self.assertEqual(r.returncode, 0, r.stderr)
        text = panel_case_text(self.CASE)
        message = self.check_error(text.replace("modes: ", "modes: 0 #"), "shell.analysis.modes", "modes:")
        self.assertIn("must be in [1, 200], got 0", message)
        message = self.check_error(text.replace("modes: ", "mods: "), "shell.analysis.mods", "mods:")
        self.assertIn("unknown key; did you mean 'modes'?", message)
        message = self.check_error(text.replace("    modes: ", "    scheme: midpoint\n    modes: "),
                                   "shell.analysis.scheme", "scheme:")
        self.assertIn("applies only to analyses of type 'dynamic'", message)

    def test_supports_along_rotated_directions_give_the_same_frequencies(self):
        # The strip turned by 30 degrees about x, its symmetry planes with the turned normal:
        # the sides get local node frames (ShellModel::to_local), the frequencies must not move.
        with open(os.path.join(ROOT, "cases", "shell", "strip_20x1.geo")) as f:
            geo = f.read().replace('Physical Curve("leading_edge")',
                                   'Rotate {{1, 0, 0}, {0, 0, 0}, Pi/6} { Surface{1}; }\n'
                                   'Physical Curve("leading_edge")')
        geo_path = os.path.join(self.tmp.name, "strip_turned.geo")
        with open(geo_path, "w") as f:
            f.write(geo)
        with open(self.CASE) as f:
            text = f.read().replace("geo: strip_20x1.geo", "geo: " + geo_path)
        text = text.replace("normal: [0, 0, 1]", "normal: [0, -0.5, 0.8660254037844386]")
        path = os.path.join(self.tmp.name, "turned_modal.yaml")
        with open(path, "w") as f:
            f.write(text)
        out = os.path.join(self.tmp.name, "turned")
        r = shellflow("run", path, "-o", out, "--no-plot")
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(out, "modes.csv"), newline="") as f:
            turned = list(csv.DictReader(f))
        for a, b in zip(turned, self.rows()):
            self.assertAlmostEqual(float(a["frequency_hz"]), float(b["frequency_hz"]),
                                   delta=1e-7 * float(b["frequency_hz"]))
            # The transverse direction is now (0, cos 30, sin 30): kinetic energy 3/4 on y.
            self.assertAlmostEqual(float(a["kinetic_y"]) / (float(a["kinetic_y"]) + float(a["kinetic_z"])), 0.75,
                                   delta=1e-6)

    def test_a_shell_free_to_move_is_one_error_line(self):
        # Only the symmetry planes: the strip can translate in its plane and turn about z.
        text = re.sub(r"    - \{ group: \w+_edge, type: clamped \}\n", "", panel_case_text(self.CASE))
        path = os.path.join(self.tmp.name, "free_modal.yaml")
        with open(path, "w") as f:
            f.write(text)
        r = shellflow("run", path, "-o", os.path.join(self.tmp.name, "free"), "--no-plot")
        self.assertEqual(r.returncode, 1, r.stderr)
        errors = [l for l in r.stderr.splitlines() if l.startswith("shellflow: error: ")]
        self.assertEqual(len(errors), 1, r.stderr)
        self.assertIn(f"{path}:{line_of(text, 'analysis:')}: shell.analysis: ", errors[0])
        self.assertIn("no support stops the rigid-body", errors[0])


class InputHardening(unittest.TestCase):
    """Untrusted case files: `check` and `mesh` run nothing a .geo asks for, damaged .msh
    files and malformed YAML are one-line errors (no crash, no hang), `mesh --json` prints
    JSON only."""

    STRIP_GEO = os.path.join(ROOT, "cases", "panel_flutter", "panel_strip.geo")

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name

    def tearDown(self):
        self.tmp.cleanup()

    def write(self, name, text):
        path = os.path.join(self.dir, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def test_flutter_refuses_a_single_mode(self):
        # One mode cannot coalesce with another: the sweep would find no boundary and say
        # "give a wider --range" instead.
        r = shellflow("flutter", os.path.join(ROOT, "cases", "panel_flutter", "clamped_clamped_piston.yaml"), "--modes", "1", "-o", os.path.join(self.dir, "flutter"), "--no-plot")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("--modes: expected a whole number of modes from 2 to 400", r.stderr)
        self.assertIn("got '1'", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "flutter", "flutter.json")))

    def case(self, mesh_line, name="case.yaml"):
        return self.write(name, "name: strip\nmeshes:\n  shell: { %s }\nprobes:\n"
                                "  - { name: w, field: shell.displacement, group: panel }\n" % mesh_line)

    def run_in_dir(self, *args, timeout=120):
        # Gmsh runs a script's commands in the current directory: run in the case folder.
        return subprocess.run([EXE, *args], capture_output=True, text=True, timeout=timeout,
                              cwd=self.dir)

    def assert_one_line(self, r, *needles):
        self.assertEqual(r.returncode, 1, (r.returncode, r.stdout, r.stderr))
        lines = r.stderr.strip().splitlines()
        error = [l for l in lines if l.startswith("shellflow: error: ")]
        self.assertEqual(len(error), 1, r.stderr)
        others = [l for l in lines if l not in error and "] info: " not in l]  # `mesh` logs
        self.assertEqual(others, [], r.stderr)
        for needle in needles:
            self.assertIn(needle, error[0])
        return error[0]

    def test_a_huge_geo_timeout_means_no_limit(self):
        # 1e18 s overflowed the watchdog's clock, which then fired at once; it is capped at 1e6 s.
        self.write("strip.geo", open(self.STRIP_GEO).read())
        case = self.case("geo: strip.geo, order: 3")
        env = {**os.environ, "SHELLFLOW_GEO_TIMEOUT": "1e18"}
        r = subprocess.run([EXE, "mesh", case, "-o", os.path.join(self.dir, "out"), "--no-plot"], capture_output=True,
                           text=True, timeout=120, cwd=self.dir, env=env)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(os.path.exists(os.path.join(self.dir, "out", "shell.msh")))

    def test_numbers_of_the_command_line_are_finite(self):
        # nan passes CLI::PositiveNumber (nan <= 0 is false): --stop-at-wall nan never stopped.
        piston = os.path.join(ROOT, "cases", "panel_flutter", "clamped_clamped_piston.yaml")
        for args in (("run", piston, "--stop-at-wall", "nan"), ("run", piston, "--stop-at-wall", "inf"),
                     ("flutter", piston, "--range", "nan", "3")):
            with self.subTest(args[-2]):
                r = self.run_in_dir(*args)
                self.assertEqual(r.returncode, 105, r.stderr)  # CLI11's ValidationError, as for every bad option
                self.assertIn("must be a finite number", r.stderr)
                self.assertFalse(os.path.exists(os.path.join(self.dir, "out")), "nothing written")

    def test_too_few_shell_steps_per_period_are_warned(self):
        # 3 steps per flutter period flipped the growth rate's sign without a word (issue 24).
        piston = os.path.join(ROOT, "cases", "panel_flutter", "clamped_clamped_piston.yaml")
        out = os.path.join(self.dir, "coarse_step")
        r = self.run_in_dir("run", piston, "-o", out, "--no-plot", "--set", "time.step=0.004", "--set", "time.end=0.1")
        self.assertEqual(r.returncode, 0, r.stderr)
        warning = [l for l in r.stderr.splitlines() if "steps per period of the response" in l]
        self.assertEqual(len(warning), 1, r.stderr)
        # Regression pin (clamped_clamped_piston at time.step 4 ms, measured 2026-12-03): 2.8 steps, from the run's
        # own ~89 Hz; not a reference — the linear eigenvalue's 75.92 Hz would give 3.3 (docs/flutter.md).
        self.assertIn("time.step 0.004 s gives 2.8 steps per period", warning[0])
        self.assertIn("fewer than 20", warning[0])
        r = self.run_in_dir("run", piston, "-o", out, "--no-plot", "--set", "time.end=0.03")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("steps per period", r.stderr)  # the case's own step: 1e-4 s, over 100 per period

    def strip_msh(self):
        """A good .msh of the panel strip, written by `shellflow mesh`."""
        case = self.case("geo: %s, order: 3" % self.STRIP_GEO, "good.yaml")
        out = os.path.join(self.dir, "good")
        r = shellflow("mesh", case, "-o", out, "--no-plot")
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(out, "shell.msh")) as f:
            return f.read().splitlines()

    def test_a_dynamic_shell_without_density_is_refused_by_check(self):
        # It used to pass check and fail the run as "the mass matrix is singular", without the key.
        case = os.path.join(ROOT, "cases", "shell", "strip_free_vibration.yaml")
        r = shellflow("check", case, "--set", "shell.material.density=0")
        self.assertEqual(r.returncode, 1)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertIn("shell.analysis.type: a dynamic analysis needs the shell's mass; set "
                      "shell.material.density > 0", r.stderr)

    def test_geo_system_command_runs_nothing(self):
        with open(self.STRIP_GEO) as f:
            geo = f.read()
        line = geo.count("\n") + 1
        self.write("strip.geo", geo + 'System "touch INJECTED";\n')
        case = self.case("geo: strip.geo, order: 3")
        for command in (["check", case], ["mesh", case, "-o", os.path.join(self.dir, "out"), "--no-plot"]):
            r = self.run_in_dir(*command)
            self.assert_one_line(r, f"strip.geo:{line}: Gmsh command 'System' runs a shell command",
                                 "remove it")
            self.assertFalse(os.path.exists(os.path.join(self.dir, "INJECTED")), command[0])
        self.assertFalse(os.path.exists(os.path.join(self.dir, "out", "shell.msh")))

    def test_include_outside_the_folder_is_refused(self):
        with open(self.STRIP_GEO) as f:
            geo = f.read()
        self.write("strip.geo", geo + 'Include "/etc/hostname";\n')
        r = self.run_in_dir("check", self.case("geo: strip.geo"))
        self.assert_one_line(r, "strip.geo:", "absolute path")

    def test_include_inside_the_folder_works_from_a_bare_case_name(self):
        with open(self.STRIP_GEO) as f:
            geo = f.read()
        self.write("part.geo", geo)
        self.write("strip.geo", 'Include "part.geo";\n')
        self.case("geo: strip.geo", "bare.yaml")
        r = self.run_in_dir("check", "bare.yaml")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("OK", r.stdout)

    def test_geo_script_named_msh_is_not_a_mesh(self):
        with open(self.STRIP_GEO) as f:
            geo = f.read()
        self.write("strip.msh", geo + 'System "touch INJECTED";\n')
        case = self.case("msh: strip.msh")
        for command in (["check", case], ["mesh", case, "-o", os.path.join(self.dir, "out"), "--no-plot"]):
            r = self.run_in_dir(*command)
            self.assert_one_line(r, "strip.msh:1: not a Gmsh mesh file")
            self.assertFalse(os.path.exists(os.path.join(self.dir, "INJECTED")))

    def test_damaged_msh_files_exit_1_with_one_line(self):
        good = self.strip_msh()
        names = good.index("$PhysicalNames")
        end_names = good.index("$EndPhysicalNames")
        def replaced(index, text):
            lines = list(good)
            lines[index] = text
            return "\n".join(lines) + "\n"
        damaged = {
            # Gmsh 4.8 dies with SIGSEGV in GModel::setPhysicalName on these two.
            "dim99.msh": (replaced(names + 2, '99 1 "bad"'), "damaged $PhysicalNames section (line %d)" % (names + 3)),
            "endnames.msh": (replaced(end_names, '99 1 "bad"'), "damaged $PhysicalNames section"),
            "count.msh": (replaced(names + 1, "x4"), "damaged $PhysicalNames section"),
            "nodes.msh": (replaced(good.index("$EndNodes"), "$EndNode"), "damaged $Nodes section"),
            "cut.msh": ("\n".join(good[: len(good) // 2]) + "\n", "damaged $Nodes section"),
            "binary.msh": (replaced(1, "4.1 1 8"), "binary .msh files are not supported"),
            # Control bytes (here a terminal escape) are shown as \xNN, not sent to the terminal.
            "rawbytes.msh": (replaced(end_names, "$EndPhysicalNames\x01\x1b[31m"),
                             "got '$EndPhysicalNames\\x01\\x1b[31m'"),
            "empty.msh": ("", "empty.msh: empty file; "),
        }
        for name, (text, expected) in damaged.items():
            self.write(name, text)
            case = self.case("msh: %s" % name, name + ".yaml")
            r = self.run_in_dir("check", case)
            self.assertGreaterEqual(r.returncode, 0, f"{name}: killed by signal {-r.returncode}")
            message = self.assert_one_line(r, name, expected)
            self.assertFalse(any(ord(ch) < 0x20 for ch in message), repr(message))
            if name != "empty.msh":
                self.assertIn("re-export the mesh from Gmsh", message)
            r = self.run_in_dir("mesh", case, "-o", os.path.join(self.dir, "out"), "--no-plot")
            self.assertGreaterEqual(r.returncode, 0, f"{name}: killed by signal {-r.returncode}")
            self.assert_one_line(r, name, expected)

    def test_malformed_yaml_fails_fast_with_one_line(self):
        import time
        for text in (",", "]", "{", "- [", ": :", "---", ",\n,", "a: 1\n,", "}"):
            path = self.write("bad.yaml", text)
            start = time.monotonic()
            try:
                r = subprocess.run([EXE, "check", path], capture_output=True, text=True, timeout=10)
            except subprocess.TimeoutExpired:
                self.fail(f"check of {text!r} hangs")
            elapsed = time.monotonic() - start
            self.assertLess(elapsed, 1.0, text)
            self.assertEqual(r.returncode, 1, (text, r.stderr))
            lines = r.stderr.strip().splitlines()
            self.assertEqual(len(lines), 1, r.stderr)
            self.assertIn(path + ":", lines[0])

    def test_a_static_run_draws_the_probes_reference_curves(self):
        # sze31_end_shear.yaml names the exact elastica (reference_sze31.csv) for both probes.
        out = os.path.join(self.dir, "out")
        r = shellflow("run", os.path.join(ROOT, "cases", "shell", "sze31_end_shear.yaml"), "-o", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("plot_probes: tip_u: reference -1 x reference_sze31.csv:minus_u_tip (21 points)", r.stdout)
        self.assertIn("plot_probes: tip_w: reference 1 x reference_sze31.csv:w_tip (21 points)", r.stdout)
        self.assertTrue(os.path.getsize(os.path.join(out, "probes.png")) > 1000)
        # `check` reads the reference: a column it lacks is refused at the key.
        text = open(os.path.join(ROOT, "cases", "shell", "sze31_end_shear.yaml")).read()
        text = text.replace("sze31_cantilever_8x1.geo", os.path.join(ROOT, "cases", "shell", "sze31_cantilever_8x1.geo"))
        text = text.replace("file: reference_sze31.csv", "file: " + os.path.join(ROOT, "cases", "shell", "reference_sze31.csv"))
        case = self.write("ref.yaml", text.replace("column: w_tip", "column: W_tip"))
        self.assert_one_line(shellflow("check", case), "ref.yaml:%d: probes[1].reference.column: no column 'W_tip'"
                             % line_of(text, "column: w_tip"), "did you mean 'w_tip'?")

    def test_mesh_json_stdout_is_only_json(self):
        case = self.case("geo: %s, order: 3" % self.STRIP_GEO)
        out = os.path.join(self.dir, "out")
        r = shellflow("mesh", case, "-o", out, "--json")  # with the plot
        self.assertEqual(r.returncode, 0, r.stderr)
        report = json.loads(r.stdout)
        self.assertEqual(report["shell"]["elements"], 40)
        self.assertTrue(os.path.getsize(os.path.join(out, "meshes.png")) > 1000)


    # ---- non-finite values name their key, the time and the cause (issue 14, defect 6) ----

    STRIP_DYNAMIC = os.path.join(ROOT, "cases", "shell", "strip_free_vibration.yaml")
    ENTROPY_WAVE = os.path.join(ROOT, "cases", "fluid", "entropy_wave.yaml")

    def assert_non_finite(self, r, *needles, wrong=()):
        message = self.assert_one_line(r, *needles, "the expression must stay finite over the run")
        for cause in wrong:
            self.assertNotIn(cause, message)
        return message

    def test_a_nan_mode_amplitude_stops_the_mesh_motion_naming_key_and_time(self):
        with open(os.path.join(ROOT, "cases", "motion", "panel_single_mode.yaml")) as f:
            text = f.read()
        text = text.replace("../panel_flutter", os.path.join(ROOT, "cases", "panel_flutter"))
        ramp = "{ type: ramp, value: 0.12, duration: 1.0 }"
        self.assertIn(ramp, text)
        text = text.replace(ramp, '{ type: expression, value: "0.02*sqrt(0.1 - t)" }')
        case = self.write("nan_amplitude.yaml", text)
        out = os.path.join(self.dir, "out")
        # Steps at 0.04 s: finite at 0, 0.04, 0.08, NaN at 0.12 (no step lands on 0.1).
        r = shellflow("run", case, "-o", out, "--no-plot", "--set", "time.end=0.2", "--set", "time.step=0.04")
        self.assert_non_finite(r, "nan_amplitude.yaml:%d: motion.prescribed.modes[0].amplitude: is NaN at t = 0.12 s"
                               % line_of(text, "sqrt(0.1 - t)"), "(sqrt of a negative number?)",
                               wrong=("valid throughout",))
        self.assertNotIn("valid throughout", r.stderr)
        # The states before stay readable.
        import xml.etree.ElementTree as ET
        files = [d.get("file") for d in ET.parse(os.path.join(out, "fluid.pvd")).getroot().iter("DataSet")]
        self.assertEqual(files[0], "fluid_000000.vtu")
        for name in files:
            self.assertTrue(os.path.exists(os.path.join(out, name)), name)
        self.assertEqual([f for f in os.listdir(out) if f.endswith(".tmp")], [])

    def test_a_nan_shell_load_names_the_load_function_not_the_solver(self):
        out = os.path.join(self.dir, "out")
        line = line_of(open(self.STRIP_DYNAMIC).read(), "load_function")
        # NaN from the start: was "the mass matrix is singular".
        r = shellflow("run", self.STRIP_DYNAMIC, "-o", out, "--no-plot", "--set", "time.end=0.002",
                      "--set", 'shell.analysis.load_function={type: expression, value: "sqrt(-1)"}')
        self.assert_non_finite(r, "strip_free_vibration.yaml:%d: shell.analysis.load_function: is NaN at t = 0 s" % line,
                               "(sqrt of a negative number?)", wrong=("mass matrix", "Newton"))
        # NaN from t = 1 ms (the second step at dt = 0.5 ms): was "Newton did not converge".
        r = shellflow("run", self.STRIP_DYNAMIC, "-o", out, "--no-plot", "--set", "time.end=0.003",
                      "--set", 'shell.analysis.load_function={type: expression, value: "(t - 0.001)/(t - 0.001)"}')
        self.assert_non_finite(r, "shell.analysis.load_function: is NaN at t = 0.001 s", "(division by zero?)",
                               wrong=("mass matrix", "Newton", "time step"))
        with open(os.path.join(out, "probes.csv")) as f:
            rows = f.read().splitlines()
        self.assertEqual(len(rows), 3)  # the header, t = 0 and t = 0.5 ms: whole rows only

    def test_an_infinite_initial_density_names_the_key_not_the_cfl_number(self):
        out = os.path.join(self.dir, "out")
        r = shellflow("run", self.ENTROPY_WAVE, "-o", out, "--no-plot", "--set", "time.end=0.01",
                      "--set", 'fluid.analysis.initial={density: "1e200*1e200*(1 + x)", velocity: [2, 0, 0], pressure: 1}')
        self.assert_non_finite(r, "entropy_wave.yaml:", "fluid.analysis.initial.density: is inf at (x, y, z) = (",
                               "t = 0 s", "(overflow in a product?)", wrong=("CFL", "cfl"))
        # A prescribed fluid mesh motion that turns NaN later.
        r = shellflow("run", self.ENTROPY_WAVE, "-o", out, "--no-plot", "--set", "time.end=0.05",
                      "--set", 'fluid.mesh_motion={displacement: ["0.05*sin(pi*x)*sqrt(0.01 - t)", 0, 0]}')
        message = self.assert_non_finite(r, "fluid.mesh_motion.displacement[0]: is NaN at (x, y, z) = (",
                                         "(sqrt of a negative number?)")
        self.assertGreater(float(re.search(r"t = ([0-9.e+-]+) s", message).group(1)), 0.01)

    # ---- a run removes the numbered output of an earlier run (issue 14, defect 7) ----

    def test_a_shorter_run_into_the_same_folder_leaves_no_stale_frames(self):
        out = os.path.join(self.dir, "out")
        # 3 output frames after the initial one (every 10 steps of 0.5 ms).
        r = shellflow("run", self.STRIP_DYNAMIC, "-o", out, "--no-plot", "--set", "time.end=0.015")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(os.path.exists(os.path.join(out, "shell_000030.vtu")))
        kept = {"notes.txt": "mine", "shell_000003.txt": "mine too", "shell.vtu.bak": "x"}
        for name, text in kept.items():
            with open(os.path.join(out, name), "w") as f:
                f.write(text)
        with open(os.path.join(out, "shell_000040.vtu.tmp"), "w") as f:
            f.write("left by a crash")
        os.makedirs(os.path.join(out, "points", "mach_2"))  # folders are never touched
        with open(os.path.join(out, "points", "mach_2", "shell_000001.vtu"), "w") as f:
            f.write("a point's run")
        r = shellflow("run", self.STRIP_DYNAMIC, "-o", out, "--no-plot", "--set", "time.end=0.005")
        self.assertEqual(r.returncode, 0, r.stderr)
        # shell_000000/10/20/30.vtu, shell.pvd, probes.csv and the .tmp.
        self.assertIn("removed 7 file(s) of an earlier run", r.stderr)
        files = sorted(os.listdir(out))
        self.assertEqual([f for f in files if f.startswith("shell_0") and f.endswith(".vtu")], ["shell_000000.vtu", "shell_000010.vtu"])
        self.assertNotIn("shell_000040.vtu.tmp", files)
        import xml.etree.ElementTree as ET
        listed = [d.get("file") for d in ET.parse(os.path.join(out, "shell.pvd")).getroot().iter("DataSet")]
        self.assertEqual(listed, ["shell_000000.vtu", "shell_000010.vtu"])
        for name, text in kept.items():
            with open(os.path.join(out, name)) as f:
                self.assertEqual(f.read(), text)
        self.assertTrue(os.path.exists(os.path.join(out, "points", "mach_2", "shell_000001.vtu")))
        with open(os.path.join(out, "probes.csv")) as f:
            self.assertEqual(len(f.read().splitlines()), 12)  # header + t = 0 + 10 steps


class FlutterAnalysis(unittest.TestCase):
    """`shellflow flutter` (linear flutter analysis) and `shellflow study` (boundary search from
    time runs) on the piston-theory panel cases (docs/flutter.md)."""

    CLAMPED = os.path.join(ROOT, "cases", "panel_flutter", "clamped_clamped_piston.yaml")
    MONOLITHIC = os.path.join(ROOT, "cases", "panel_flutter", "clamped_sliding_piston_monolithic.yaml")

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def flutter(self, *args, case=None):
        out = os.path.join(self.tmp.name, "flutter")
        r = shellflow("flutter", case or self.CLAMPED, "-o", out, "--json", *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        return json.loads(r.stdout), out  # stdout is the JSON object and nothing else

    def test_dowell_clamped_boundary_without_aerodynamic_damping(self):
        d, out = self.flutter("--no-aero-damping")
        # Dowell's clamped-clamped panel, mu/M -> 0: lambda_cr = 636.6 (docs/flutter.md).
        self.assertLess(abs(d["lambda_cr"] / 636.6 - 1), 0.005)
        self.assertLess(abs(d["critical_value_half_modes"] / d["lambda_cr"] - 1), 1e-4)  # basis converged
        self.assertGreater(d["frequency_hz"], d["in_vacuo_frequencies_hz"][0])
        self.assertLess(d["frequency_hz"], d["in_vacuo_frequencies_hz"][1])
        for name in ("flutter_locus.csv", "flutter.json", "flutter_locus.png"):
            self.assertTrue(os.path.getsize(os.path.join(out, name)) > 100, name)
        with open(os.path.join(out, "flutter_locus.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 50 * 24)  # 50 values x 24 roots

    def test_mach_sweep_and_the_case_point(self):
        d, _ = self.flutter("--parameter", "mach")
        # At rho and p of the case: the boundary between Mach 2.0 and 2.02 (docs/flutter.md);
        # the case's own point (Mach 2.3) is unstable with the growth of the time runs' check.
        # Dowell's lambda_cr 636.6 (no aerodynamic damping) is Mach 2.001 here; the damping raises
        # the linear analysis's boundary to 2.0112 (docs/flutter.md).
        self.assertGreater(d["mach_cr"], 2.0)
        self.assertLess(d["mach_cr"], 2.02)
        # The case's lambda = rho U^2 L^3 / (D sqrt(M^2 - 1)) = 703.8212528 at Mach 2.3, scaled to M_cr
        # (U^2 / sqrt(M^2 - 1) goes as M^2 / sqrt(M^2 - 1) at fixed rho and p).
        self.assertAlmostEqual(d["lambda_cr"], 703.8212528 * (d["mach_cr"] ** 2 / math.sqrt(d["mach_cr"] ** 2 - 1))
                               / (2.3 ** 2 / math.sqrt(2.3 ** 2 - 1)), delta=1e-3)
        # Regression pin (20 x 1 cubic strip, shellflow's linear analysis, measured 2026-12-01): 51.605 1/s at Mach
        # 2.3; not a reference — the 8-mode beam model of the design notes gives 51.6 1/s (docs/coupling.md).
        self.assertLess(abs(d["case_growth_rate"] / 51.605 - 1), 1e-3)

    def test_a_range_without_boundary_says_so(self):
        out = os.path.join(self.tmp.name, "flutter")
        r = shellflow("flutter", self.CLAMPED, "-o", out, "--json", "--range", "0", "300", "--no-plot")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIsNone(json.loads(r.stdout)["lambda_cr"])
        self.assertIn("no flutter boundary in lambda = [0, 300]", r.stderr)

    def test_bad_flutter_input_is_one_line(self):
        r = shellflow("flutter", self.CLAMPED, "-o", os.path.join(self.tmp.name, "x"), "--parameter", "mach",
                      "--no-aero-damping")
        self.assertEqual(r.returncode, 1)
        self.assertIn("--no-aero-damping applies to --parameter lambda only", r.stderr)
        shell = os.path.join(ROOT, "cases", "shell", "strip_modal.yaml")
        r = shellflow("flutter", shell, "-o", os.path.join(self.tmp.name, "y"))
        self.assertEqual(r.returncode, 1)
        self.assertIn("needs a 'fluid' section", r.stderr)
        r = shellflow("run", self.CLAMPED, "-o", os.path.join(self.tmp.name, "z"), "--set", "fluid.free_stream=2")
        self.assertEqual(r.returncode, 1)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)

    def study(self, out, *sets, returncode=0):
        args = ["study", self.MONOLITHIC, "-o", out, "-j", "2", "--no-plot", "--json"]
        for s in sets:
            args += ["--set", s]
        r = shellflow(*args)
        self.assertEqual(r.returncode, returncode, r.stderr)
        return (json.loads(r.stdout) if returncode == 0 else None), r

    def test_study_finds_the_linear_boundary_and_resumes(self):
        d_lin, _ = self.flutter("--parameter", "mach", case=self.MONOLITHIC)
        out = os.path.join(self.tmp.name, "study")
        sets = ("study.range=[1.95, 2.1]", "study.points=3", "study.tolerance=0.005")
        d, r = self.study(out, *sets)
        self.assertIsNotNone(d["boundary"], r.stderr)
        # The monolithic scheme has no time lag: the time runs' boundary is the linear one.
        self.assertLess(abs(d["boundary"] - d_lin["mach_cr"]), d["tolerance"])
        lo, hi = d["bracket"]
        self.assertLessEqual(hi - lo, d["tolerance"])
        with open(os.path.join(out, "study.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), len(d["points"]))
        self.assertTrue(all(row["status"] == "ok" for row in rows))
        # Resumed: nothing is rerun, the answer is the same (study.* keys do not change a run).
        d2, r2 = self.study(out, *sets, "study.max_refinements=12")
        self.assertNotIn("study: run ", r2.stderr)
        self.assertEqual(d2["boundary"], d["boundary"])
        # A key that changes the runs reruns them (here 5 ms runs, which give the study no growth
        # rate: only the rerun is asserted).
        _, r3 = self.study(out, *sets, "time.end=0.005", returncode=1)
        self.assertIn("was run with other settings; rerun", r3.stderr)
        self.assertIn("none of the 3 runs gave a growth rate", r3.stderr)

    def test_study_marks_failed_runs_and_reports_a_missing_bracket(self):
        # A 1 micrometre panel under the start-up pulse: Newton gives up in the run (a failed point,
        # the study goes on); the 1.35 mm one grows (Mach 2.3): no sign change in the range.
        out = os.path.join(self.tmp.name, "study")
        d, r = self.study(out, "study.parameter=thickness", "study.range=[1e-6, 1.35e-3]", "study.points=2",
                          "study.set={time.end: 0.05, coupling.response.window: [0.005, 1.0]}")
        self.assertIsNone(d["boundary"])
        self.assertIn("does not change sign", r.stderr)
        failed = [p for p in d["points"] if not p["ok"]]
        self.assertEqual(len(failed), 1)
        self.assertIn("Newton did not converge", failed[0]["message"])
        self.assertTrue(any(p["ok"] and p["growth_rate"] > 0 for p in d["points"]))
        with open(os.path.join(out, "study.csv"), newline="") as f:
            self.assertEqual(sorted(row["status"] for row in csv.DictReader(f)), ["failed", "ok"])

    def test_a_study_where_no_run_gives_a_growth_rate_fails_with_the_reason(self):
        # --set time.end on the command line wins over the case's study.set (0.25 s): 5 ms runs
        # are too short for a growth rate at every point: no result, exit 1, the runs' reason.
        out = os.path.join(self.tmp.name, "study")
        r = shellflow("study", self.MONOLITHIC, "-o", out, "--no-plot", "--set", "study.points=2",
                      "--set", "time.end=0.005")
        self.assertEqual(r.returncode, 1, r.stderr)
        last = r.stderr.strip().splitlines()[-1]
        self.assertRegex(last, r"^shellflow: error: study: none of the 2 runs gave a growth rate \(at mach = 1.8: "
                               r"response.json has no growth rate")
        self.assertNotIn("widen study.range", r.stderr)
        with open(os.path.join(out, "study.csv"), newline="") as f:
            self.assertEqual([row["status"] for row in csv.DictReader(f)], ["failed", "failed"])

    def test_a_study_range_the_runs_cannot_take_is_refused_before_running(self):
        # Dynamic pressure 15876 Pa is Mach 0.9 at this p: piston theory cannot run it.
        out = os.path.join(self.tmp.name, "study")
        r = shellflow("study", self.MONOLITHIC, "-o", out, "--set", "study.parameter=dynamic_pressure",
                      "--set", "study.range=[15876, 50000]")
        self.assertEqual(r.returncode, 1)
        self.assertIn("study at dynamic_pressure = 15876", r.stderr)
        self.assertIn("supersonic", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(out, "points")))

    def test_a_study_of_an_unknown_probe_runs_nothing(self):
        out = os.path.join(self.tmp.name, "study")
        r = shellflow("study", self.MONOLITHIC, "-o", out, "--set", "coupling.response.probe=w_nowhere")
        self.assertEqual(r.returncode, 1)
        self.assertIn("w_nowhere", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(out, "points")))


class IdentifiedFlutter(unittest.TestCase):
    """`shellflow flutter --aerodynamics identified` (docs/flutter.md, "Identified aerodynamics"): the
    forced-motion identification run of the case's own flow and the discrete flutter analysis."""

    MONOLITHIC = os.path.join(ROOT, "cases", "panel_flutter", "clamped_sliding_piston_monolithic.yaml")
    COARSE = os.path.join(ROOT, "cases", "panel_flutter", "clamped_sliding_coarse.yaml")

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def flutter(self, case, out, *args):
        r = shellflow("flutter", case, "-o", out, "--json", "--no-plot", *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        return json.loads(r.stdout), r.stderr

    def test_identified_piston_theory_returns_the_piston_analysis(self):
        # Piston theory driven through the forced-motion path, fitted (one tap of [q; q']) and
        # solved with Newmark at the shell step (the monolithic case: the forces of the step's
        # end): the trapezoidal rule maps Re s = 0 onto |z| = 1, so lambda_cr and M_cr are the
        # continuous analysis's; the frequency is warped to atan(pi f dt') / (pi dt').
        out = os.path.join(self.tmp.name, "identified")
        d, err = self.flutter(self.MONOLITHIC, out, "--aerodynamics", "identified")
        p, _ = self.flutter(self.MONOLITHIC, os.path.join(self.tmp.name, "piston"), "--modes", "6")
        self.assertEqual(d["aerodynamics"], "identified")
        self.assertEqual(d["identification"]["coupling"], "simultaneous")
        self.assertLess(d["identification"]["residual"], 1e-12)
        self.assertLess(abs(d["lambda_cr"] / p["lambda_cr"] - 1), 1e-6)
        self.assertLess(abs(d["mach_cr"] - p["mach_cr"]), 1e-6)
        # The model's step at lambda_cr (fixed Mach: U goes as sqrt(lambda)): dt U_case / U.
        step = 1e-4 * math.sqrt(d["lambda_case"] / d["lambda_cr"])
        f = p["frequency_hz"]
        self.assertLess(abs(d["frequency_hz"] - math.atan(math.pi * f * step) / (math.pi * step)), 1e-6 * f)
        for name in ("gaf_record.csv", "gaf.json"):
            self.assertTrue(os.path.getsize(os.path.join(out, "identification", name)) > 100, name)
        # The same case again reuses the identification.
        d2, err2 = self.flutter(self.MONOLITHIC, out, "--aerodynamics", "identified")
        self.assertIn("reusing the identification", err2)
        self.assertTrue(d2["identification"]["reused"])
        self.assertEqual(d2["lambda_cr"], d["lambda_cr"])
        # What an identified model cannot do is one line each.
        for extra, message in ((["--no-aero-damping"], "cannot be split into a stiffness and a damping part"),
                               (["--direct"], "works on the modal basis")):
            r = shellflow("flutter", self.MONOLITHIC, "-o", out, "--aerodynamics", "identified", *extra)
            self.assertEqual(r.returncode, 1, r.stderr)
            self.assertIn(message, r.stderr)
            self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)

    def test_two_identification_mach_numbers_and_a_thicker_plate(self):
        # Identified at Mach 1.9 and 2.1 around the boundary, the taps interpolated in Mach: piston
        # theory with its damping factor c(M) interpolated linearly, M_cr 2.0091356 (the unit test
        # ForcedMotion.TwoIdentificationsInterpolateInMach) against 2.0092937 of piston theory, where
        # one identification at the case's Mach 2.3 gives 2.0126584 (c frozen at 2.3).
        out = os.path.join(self.tmp.name, "two")
        d, _ = self.flutter(self.MONOLITHIC, out, "--aerodynamics", "identified", "--parameter", "mach",
                            "--identification-mach", "2.1", "1.9")
        p, _ = self.flutter(self.MONOLITHIC, os.path.join(self.tmp.name, "piston"), "--modes", "6",
                            "--parameter", "mach")
        self.assertEqual(d["identification"]["identification_mach"], [1.9, 2.1])
        self.assertEqual([r["mach"] for r in d["identification"]["runs"]], [1.9, 2.1])
        for m in ("1.9", "2.1"):
            self.assertTrue(os.path.exists(os.path.join(out, "identification_mach_" + m, "gaf_modes.csv")), m)
        self.assertAlmostEqual(d["mach_cr"], 2.0091356, delta=1e-6)
        self.assertAlmostEqual(p["mach_cr"], 2.0092937, delta=1e-6)
        # A thicker plate reuses the identification at 1.9 alone: its modes on the mid-surface are
        # combinations of the identified ones to 1.4e-4, and the model carried over to them gives
        # the lambda_cr of an identification of the thicker plate itself.
        args = ("--aerodynamics", "identified", "--identification-mach", "1.9", "--set", "shell.thickness=1.6e-3")
        t, err = self.flutter(self.MONOLITHIC, out, *args)
        fresh, _ = self.flutter(self.MONOLITHIC, os.path.join(self.tmp.name, "thick"), *args)
        self.assertIn("are combinations of the identified ones", err)
        self.assertTrue(t["identification"]["reused"])
        self.assertFalse(fresh["identification"]["reused"])
        self.assertLess(t["identification"]["runs"][0]["mode_residual"], 1e-3)
        self.assertLess(abs(t["lambda_cr"] / fresh["lambda_cr"] - 1), 1e-5)
        # Other supports change the mode shapes: the identification is made anew.
        supports = ("shell.supports=[{group: leading_edge, type: simply_supported}, {group: trailing_edge, "
                    "type: sliding, direction: [1, 0, 0], clamp_director: true}, {group: sides, type: symmetry, "
                    "normal: [0, 0, 1]}]")
        s, err = self.flutter(self.MONOLITHIC, out, "--aerodynamics", "identified", "--identification-mach", "1.9",
                              "--set", supports)
        self.assertIn("are not combinations of the identified ones", err)
        self.assertFalse(s["identification"]["reused"])
        r = shellflow("flutter", self.MONOLITHIC, "-o", out, "--identification-mach", "1.9")
        self.assertEqual(r.returncode, 1, r.stderr)
        self.assertIn("applies to --aerodynamics identified", r.stderr)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)

    def test_euler_identification_on_the_coarse_strip(self):
        # The coarse strip at Mach 2.3 (614 shell steps of flow, no shell solve, 23 s; the analysis 13 s): the FIR fits the
        # record to 2e-5, and the staggered discrete analysis gives M_cr 1.99967 and the case's growth
        # 53.18 1/s at 75.71 Hz. Against the coupled time run at Mach 2.3 on this mesh (52.94 1/s,
        # 75.72 Hz): +0.45 % and -0.02 % (docs/flutter.md). Regression pins, measured 2026-12-07.
        d, err = self.flutter(self.COARSE, os.path.join(self.tmp.name, "euler"), "--aerodynamics", "identified")
        self.assertEqual(d["identification"]["coupling"], "staggered")
        self.assertEqual(d["identification"]["taps"], 24)
        self.assertLess(d["identification"]["residual"], 5e-5)
        self.assertAlmostEqual(d["mach_cr"], 1.99967, delta=2e-4)
        self.assertLess(abs(d["case_growth_rate"] / 52.94 - 1), 0.02)
        self.assertLess(abs(d["case_frequency_hz"] / 75.724 - 1), 0.002)


class Plates3D(unittest.TestCase):
    """The 3-D panels of cases/panel_3d/ (docs/flutter.md, "3-D panels") from the command line:
    check, the linear analysis with its mode shapes, and a short plate run with its plots."""
    CASES = os.path.join(ROOT, "cases", "panel_3d")
    NAMES = ("clamped_square_piston", "simply_supported_square_piston", "rectangle_2x1_piston",
             "cylindrical_panel_piston", "clamped_square", "clamped_square_coarse")

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def test_check_accepts_every_3d_case(self):
        for name in self.NAMES:
            r = shellflow("check", os.path.join(self.CASES, name + ".yaml"))
            self.assertEqual(r.returncode, 0, name + ": " + r.stderr)

    def test_clamped_square_boundary_and_mode_shapes(self):
        out = os.path.join(self.tmp.name, "flutter")
        r = shellflow("flutter", os.path.join(self.CASES, "clamped_square_piston.yaml"), "-o", out, "--json",
                      "--parameter", "mach")
        self.assertEqual(r.returncode, 0, r.stderr)
        d = json.loads(r.stdout)
        # M_cr 2.936 at the strip cases' altitude (lambda_cr 860.6 with the aerodynamic damping;
        # 856.1 without it on this 12 x 12 grid against 851.2 of the Ritz model, docs/flutter.md).
        # Regression pin (12 x 12 cubic grid, with the aerodynamic damping, measured 2026-12-03): M_cr 2.936;
        # not a reference — the Ritz model's 851.2 (no damping) is Mach 2.899 at this altitude.
        self.assertGreater(d["mach_cr"], 2.9)
        self.assertLess(d["mach_cr"], 2.97)
        # Leissa's clamped square: omega a^2 sqrt(rho h / D) = 35.99, 50.51 Hz for this plate.
        self.assertLess(abs(d["in_vacuo_frequencies_hz"][0] / 50.51 - 1), 0.005)
        # Modes 2 and 3 are the square's pair (2,1)/(1,2); the grid's diagonals split them by 0.13 %.
        self.assertLess(abs(d["in_vacuo_frequencies_hz"][1] / d["in_vacuo_frequencies_hz"][2] - 1), 0.005)
        arrays = read_vtu_point_arrays(os.path.join(out, "flutter_modes.vtu"))
        for name in ("mode_01", "mode_06", "flutter_mode_re", "flutter_mode_im"):
            self.assertEqual(len(arrays[name]), len(arrays["Points"]), name)
        # The first mode: all of one sign, largest at the centre (0.5, 0, 0) of the plate.
        w1 = [v[1] for v in arrays["mode_01"]]
        centre = min(range(len(w1)), key=lambda i: math.dist(arrays["Points"][i], (0.5, 0.0, 0.0)))
        self.assertAlmostEqual(max(w1), 1.0, places=12)
        self.assertAlmostEqual(w1[centre], 1.0, places=2)
        self.assertGreater(min(w1), -1e-5)  # one sign (the cubic nodes next to a clamp dip by ~3e-6)
        # The flutter mode: its largest component real and 1, downstream of the centre.
        re = [v[1] for v in arrays["flutter_mode_re"]]
        peak = max(range(len(re)), key=lambda i: abs(re[i]))
        self.assertAlmostEqual(re[peak], 1.0, places=12)
        self.assertAlmostEqual(arrays["flutter_mode_im"][peak][1], 0.0, places=12)
        self.assertGreater(arrays["Points"][peak][0], 0.5)
        self.assertTrue(os.path.getsize(os.path.join(out, "flutter_modes.png")) > 1000)

    def test_short_plate_run_draws_its_deflection(self):
        out = os.path.join(self.tmp.name, "run")
        r = shellflow("run", os.path.join(self.CASES, "clamped_square_piston.yaml"), "-o", out, "--set",
                      "time.end=0.005", "--set", "meshes.shell.size_factor=2")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(os.path.getsize(os.path.join(out, "deflection.png")) > 1000)
        with open(os.path.join(out, "probes.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 51)
        # The cavity dip pushes the plate down (into the cavity) in its first steps.
        self.assertLess(float(rows[-1]["w_x0600"]), 0.0)


    def test_euler_half_model_coarse_flutters(self):
        # The 3-D Euler case's CI variant (60 ms on the coarse box, a 1e-6 dip): the plate
        # flutters at about piston theory's rate and frequency, the loads the shell receives
        # carry the fluid's resultant, the gas does not cross the symmetry plane.
        out = os.path.join(self.tmp.name, "euler")
        r = shellflow("run", os.path.join(self.CASES, "clamped_square_coarse.yaml"), "-o", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(out, "response.json")) as f:
            response = json.load(f)
        # The potential-flow reference carried over to the half model's shell: 73.31 1/s at
        # 96.20 Hz (coupling.md; piston theory 69.05 1/s at 96.95 Hz). On 18.75 mm cells the
        # Euler flow is 5.8 % above it; the band allows 10 %.
        self.assertGreater(response["growth_rate"], 0.9 * 73.31)
        self.assertLess(response["growth_rate"], 1.1 * 73.31)
        self.assertLess(abs(response["frequency_hz"] / 96.20 - 1), 0.03)
        # Regression pin (this mesh and scheme, measured 2026-12-07): 77.57 1/s at 96.02 Hz.
        self.assertAlmostEqual(response["growth_rate"], 77.57, delta=0.01 * 77.57)
        self.assertAlmostEqual(response["frequency_hz"], 96.02, delta=0.005 * 96.02)
        with open(os.path.join(out, "probes.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 601)
        # The dip lowers the cavity pressure: the plate first moves into the cavity (w < 0).
        first = next(float(row["w_x0600"]) for row in rows if abs(float(row["w_x0600"])) > 1e-12)
        self.assertLess(first, 0.0)
        with open(os.path.join(out, "coupling.csv"), newline="") as f:
            steps = list(csv.DictReader(f))
        largest = max(abs(float(s["fluid_force_y"])) for s in steps)
        mismatch = max(abs(float(s["shell_force_y"]) - float(s["fluid_force_y"])) for s in steps)
        self.assertGreater(largest, 0.0)
        self.assertLess(mismatch / largest, 0.015)  # measured 1.2 %
        fluid = read_vtu_point_arrays(os.path.join(out, "fluid_000600.vtu"))
        speed = 3.5 * math.sqrt(1.4 * 28000 / 0.339)
        on_plane = [i for i, x in enumerate(fluid["Points"]) if abs(x[2]) < 1e-12]
        self.assertGreater(len(on_plane), 100)
        self.assertLess(max(abs(fluid["velocity"][i][2]) for i in on_plane), 1e-10 * speed)
        for name in ("deflection.png", "flutter.png", "mesh_quality.png", "fluid.pvd", "space.pvd"):
            self.assertTrue(os.path.getsize(os.path.join(out, name)) > 100, name)

    def test_euler_half_model_coarse_moves_its_mesh(self):
        # With a 1e-3 dip the plate bends by about 0.1 mm in 10 ms: the moving 3-D mesh keeps
        # its quality and the mean panel pressure stays within 1 % of the free stream.
        out = os.path.join(self.tmp.name, "euler_dip")
        r = shellflow("run", os.path.join(self.CASES, "clamped_square_coarse.yaml"), "-o", out, "--no-plot",
                      "--set", "time.end=0.01", "--set",
                      "coupling.cavity_pressure.value=28000*(1 - 0.001*step(0.004 - t))")
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(out, "probes.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 101)
        w = [abs(float(row["w_x0600"])) for row in rows]
        self.assertGreater(max(w), 1e-5)  # the dip's 28 Pa bend the plate by ~0.1 mm
        self.assertLess(max(w), 1e-3)
        for row in rows:
            self.assertLess(abs(float(row["p_panel_mean"]) / 28000 - 1), 0.01)
        with open(os.path.join(out, "mesh_quality.csv"), newline="") as f:
            quality = list(csv.DictReader(f))
        self.assertEqual(int(quality[-1]["fluid_inverted"]), 0)
        self.assertGreater(float(quality[-1]["fluid_min_quality_ratio"]), 0.99)


class ThreadCounts(unittest.TestCase):
    """The default case gives the same bits on any thread count (docs/parallel.md "Threads")."""

    def test_default_case_on_one_two_and_three_threads_writes_the_same_files(self):
        with tempfile.TemporaryDirectory() as tmp:
            outs = []
            for threads in (1, 2, 3):
                out = os.path.join(tmp, f"out{threads}")
                env = {**os.environ, "OMP_NUM_THREADS": str(threads)}
                r = subprocess.run([EXE, "run", PANEL, "-o", out, "--no-plot", "--set", "time.end=0.002"],
                                   capture_output=True, text=True, timeout=600, env=env)
                self.assertEqual(r.returncode, 0, r.stderr)
                outs.append(out)
            names = ["probes.csv", "response.json", "coupling.csv", "fluid_000020.vtu", "shell_000020.vtu"]
            for name in names:
                with open(os.path.join(outs[0], name), "rb") as f:
                    reference = f.read()
                self.assertGreater(len(reference), 100, name)
                for out in outs[1:]:
                    with open(os.path.join(out, name), "rb") as f:
                        self.assertEqual(f.read(), reference, f"{name}: {out} differs from the 1-thread run")
            # The flow did change over the run (the comparison is not of initial states).
            p0 = read_vtu_point_arrays(os.path.join(outs[0], "fluid_000000.vtu"))
            p1 = read_vtu_point_arrays(os.path.join(outs[0], "fluid_000020.vtu"))
            key = next(k for k in p0 if k.lower().startswith("pressure"))
            self.assertTrue(any(a != b for a, b in zip(p0[key], p1[key])))


class PartitionCommand(unittest.TestCase):
    """`shellflow partition`: the default case's fluid mesh split by METIS (mesh/partition.h)."""

    def test_parts_cover_the_mesh_once_and_the_vtu_holds_the_ranks(self):
        import meshio

        with tempfile.TemporaryDirectory() as tmp:
            for parts in (2, 3):
                out = os.path.join(tmp, f"parts{parts}")
                r = shellflow("partition", PANEL, "--parts", str(parts), "-o", out)
                self.assertEqual(r.returncode, 0, r.stderr)
                self.assertIn("imbalance", r.stdout)
                with open(os.path.join(out, "partition.json")) as f:
                    stats = json.load(f)
                m = meshio.read(os.path.join(out, "partition.vtu"))
                cells = sum(len(c.data) for c in m.cells)
                self.assertEqual(stats["parts"], parts)
                self.assertEqual(stats["nodes"], len(m.points))
                self.assertEqual(stats["cells"], cells)
                per_part = stats["per_part"]
                self.assertEqual(len(per_part), parts)
                self.assertEqual(sum(p["owned_nodes"] for p in per_part), len(m.points))
                self.assertEqual(sum(p["owned_cells"] for p in per_part), cells)
                self.assertEqual(sum(p["ghost_nodes"] for p in per_part), stats["ghost_nodes"])
                for p in per_part:
                    self.assertGreater(p["ghost_nodes"], 0)
                    self.assertGreater(p["interface_nodes"], 0)
                    self.assertGreaterEqual(p["neighbours"], 1)
                    self.assertLessEqual(p["owned_cells"], 1.1 * cells / parts)
                self.assertLessEqual(stats["imbalance"], 1.1)
                rank = [int(v) for block in m.cell_data["rank"] for v in block]
                self.assertEqual(len(rank), cells)
                self.assertEqual(sorted(set(rank)), list(range(parts)))
                for p in range(parts):
                    self.assertEqual(rank.count(p), per_part[p]["owned_cells"])
                owner = [int(v) for v in m.point_data["owner"]]
                self.assertEqual(sorted(set(owner)), list(range(parts)))
                for p in range(parts):
                    self.assertEqual(owner.count(p), per_part[p]["owned_nodes"])

    def test_more_parts_than_cells_is_refused(self):
        with tempfile.TemporaryDirectory() as tmp:
            r = shellflow("partition", PANEL, "--parts", "1000000", "-o", tmp)
            self.assertEqual(r.returncode, 1, r.stderr)
            self.assertIn("the number of parts must be between 1 and", r.stderr)
            r = shellflow("partition", PANEL, "--parts", "0", "-o", tmp)
            self.assertEqual(r.returncode, 105, r.stderr)  # CLI11's ValidationError
            self.assertIn("--parts: Value 0 not in range 1 to", r.stderr)


if __name__ == "__main__":
    unittest.main()
