#!/usr/bin/env python3
"""Unit tests of tools/plot_shell_field.py on small synthetic .vtu/.pvd files written here in
shellflow's format (raw appended data, a UInt64 byte count before every array).

usage: /usr/bin/python3 tests/app/test_plot_shell_field.py -v   (from the source tree)
"""
import contextlib
import importlib.util
import io
import math
import os
import sys
import tempfile
import unittest

sys.dont_write_bytecode = True  # importing the tool must not write tools/__pycache__

import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
_spec = importlib.util.spec_from_file_location("plot_shell_field", os.path.join(ROOT, "tools", "plot_shell_field.py"))
psf = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(psf)

# VTK_LAGRANGE_TRIANGLE node i sits at lattice point (i, j) / 3 of the reference triangle
# (src/shellflow/io/vtu_writer.cpp): corners, edge (0,1), edge (1,2), edge (2,0), centre.
CUBIC_NODES = [(0, 0), (3, 0), (0, 3), (1, 0), (2, 0), (2, 1), (1, 2), (0, 2), (0, 1), (1, 1)]
QUADRATIC_NODES = [(0, 0), (2, 0), (0, 2), (1, 0), (1, 1), (0, 1)]


def grid_mesh(squares=2, order=3):
    """Unit square [0, 1]^2 in the plane y = 0 (x, z), squares x squares quads each split in two
    triangles of the given order (1, 2, 3): (points (n, 3), cells [[node...]], VTK type)."""
    nodes = {1: [(0, 0), (1, 0), (0, 1)], 2: QUADRATIC_NODES, 3: CUBIC_NODES}[order]
    vtk_type = {1: 5, 2: 22, 3: 69}[order]
    n = squares * order + 1  # lattice points per side
    points = np.array([[i / (n - 1), 0.0, j / (n - 1)] for j in range(n) for i in range(n)])
    cells = []
    for b in range(squares):
        for a in range(squares):
            i0, j0 = a * order, b * order
            for c0, c1, c2 in (((i0, j0), (i0 + order, j0), (i0, j0 + order)),
                               ((i0 + order, j0 + order), (i0, j0 + order), (i0 + order, j0))):
                cell = []
                for (p, q) in nodes:
                    li = c0[0] + (p * (c1[0] - c0[0]) + q * (c2[0] - c0[0])) // order
                    lj = c0[1] + (p * (c1[1] - c0[1]) + q * (c2[1] - c0[1])) // order
                    cell.append(lj * n + li)
                cells.append(cell)
    return points, cells, vtk_type


def write_vtu(path, points, cells, vtk_type, point_arrays, time=None):
    """A .vtu as shellflow's io::write_vtu writes it: point arrays (Float64), Points, then the
    cell arrays, all in one raw appended block."""
    blobs, lines, offset = [], [], 0

    def data_array(kind, name, components, array):
        nonlocal offset
        raw = np.ascontiguousarray(array).tobytes()
        extra = f' NumberOfComponents="{components}"' if components else ""
        lines.append(f'        <DataArray type="{kind}" Name="{name}"{extra} format="appended" offset="{offset}"/>')
        blobs.append(np.uint64(len(raw)).tobytes() + raw)
        offset += 8 + len(raw)

    lines.append("      <PointData>")
    for name, values in point_arrays.items():
        values = np.asarray(values, dtype="<f8").reshape(len(points), -1)
        data_array("Float64", name, values.shape[1], values)
    lines += ["      </PointData>", "      <CellData>", "      </CellData>", "      <Points>"]
    data_array("Float64", "Points", 3, np.asarray(points, dtype="<f8"))
    lines += ["      </Points>", "      <Cells>"]
    connectivity = np.array([v for c in cells for v in c], dtype="<i8")
    offsets = np.cumsum([len(c) for c in cells]).astype("<i8")
    data_array("Int64", "connectivity", 0, connectivity)
    data_array("Int64", "offsets", 0, offsets)
    data_array("UInt8", "types", 0, np.full(len(cells), vtk_type, dtype="u1"))
    lines += ["      </Cells>"]
    field = ""
    if time is not None:
        field = ('    <FieldData>\n      <DataArray type="Float64" Name="TimeValue" NumberOfTuples="1" '
                 f'format="ascii">{time!r}</DataArray>\n    </FieldData>\n')
    xml = ('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" '
           'header_type="UInt64">\n  <UnstructuredGrid>\n' + field
           + f'    <Piece NumberOfPoints="{len(points)}" NumberOfCells="{len(cells)}">\n'
           + "\n".join(lines) + "\n    </Piece>\n  </UnstructuredGrid>\n"
           + '  <AppendedData encoding="raw">\n   _')
    with open(path, "wb") as f:
        f.write(xml.encode() + b"".join(blobs) + b"\n  </AppendedData>\n</VTKFile>\n")


def write_pvd(path, frames):
    """frames: [(time, file name relative to the .pvd's folder), ...]."""
    rows = "".join(f'    <DataSet timestep="{t!r}" group="" part="0" file="{name}"/>\n' for t, name in frames)
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
                f"  <Collection>\n{rows}  </Collection>\n</VTKFile>\n")


AMPLITUDE = 1e-3  # m: w = AMPLITUDE * scale * sin(pi x) sin(pi z), largest at (0.5, 0, 0.5)


def bump(points, scale):
    """Displacement (n, 3): w along +y = AMPLITUDE * scale * sin(pi x) sin(pi z)."""
    u = np.zeros_like(points)
    u[:, 1] = AMPLITUDE * scale * np.sin(math.pi * points[:, 0]) * np.sin(math.pi * points[:, 2])
    return u


def run_main(argv):
    """(status, stdout, stderr) of psf.main(argv)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            status = psf.main(argv)
        except SystemExit as e:  # argparse
            status = e.code
    return status, out.getvalue(), err.getvalue()


class Series(unittest.TestCase):
    """A .pvd of three frames of the same bump at scales 1, 3, 2 (times 0.1, 0.2, 0.3 s)."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name
        self.points, self.cells, self.type = grid_mesh()
        names = []
        for k, scale in enumerate((1.0, 3.0, 2.0)):
            name = f"shell_{k:06}.vtu"
            write_vtu(os.path.join(self.dir, name), self.points, self.cells, self.type,
                      {"displacement": bump(self.points, scale), "thickness_parameter": np.zeros(len(self.points))},
                      time=0.1 * (k + 1))
            names.append((0.1 * (k + 1), name))
        self.pvd = os.path.join(self.dir, "shell.pvd")
        write_pvd(self.pvd, names)

    def tearDown(self):
        self.tmp.cleanup()

    def test_reads_the_file_back(self):
        data = psf.read_vtu(os.path.join(self.dir, "shell_000001.vtu"))
        np.testing.assert_array_equal(data.points, self.points)
        np.testing.assert_array_equal(data.point_data["displacement"], bump(self.points, 3.0))
        self.assertEqual(data.point_data["thickness_parameter"].shape, (len(self.points), 1))
        self.assertEqual(len(data.types), 8)
        self.assertEqual(data.connectivity.size, 80)
        self.assertAlmostEqual(data.time, 0.2, places=15)
        frames = psf.read_pvd(self.pvd)
        self.assertEqual([os.path.basename(p) for _, p in frames], [f"shell_{k:06}.vtu" for k in range(3)])

    def test_largest_frame_is_the_one_at_scale_3(self):
        frames = psf.read_pvd(self.pvd)
        index, value = psf.select_frame(frames, "displacement", "normal", "largest")
        self.assertEqual(index, 1)
        self.assertAlmostEqual(value, 3.0 * AMPLITUDE, delta=1e-12)
        self.assertEqual(psf.select_frame(frames, "displacement", "normal", "last")[0], 2)
        index, value = psf.select_frame(frames, "displacement", "y", 0)
        self.assertEqual(index, 0)
        self.assertAlmostEqual(value, AMPLITUDE, delta=1e-12)
        self.assertEqual(psf.select_frame(frames, "displacement", "normal", -1)[0], 2)
        with self.assertRaises(psf.PlotError):
            psf.select_frame(frames, "displacement", "normal", 3)

    def test_field_figure_reports_the_maximum_and_where(self):
        data = psf.read_vtu(os.path.join(self.dir, "shell_000001.vtu"))
        fig, ax, k, value = psf.field_figure(data, "displacement", "normal", 0.2)
        self.assertAlmostEqual(value, 3.0 * AMPLITUDE, delta=1e-12)
        np.testing.assert_allclose(data.points[k], [0.5, 0.0, 0.5], atol=1e-15)
        self.assertIn("at t = 0.2 s", ax.get_title())
        self.assertIn("largest |value| 3 mm at (0.5, 0, 0.5)", ax.get_title())
        self.assertEqual((ax.get_xlabel(), ax.get_ylabel()), ("x [m]", "z [m]"))
        psf.plt.close(fig)

    def test_main_writes_deflection_png_next_to_the_pvd(self):
        status, out, err = run_main([self.pvd])
        self.assertEqual(status, 0, err)
        png = os.path.join(self.dir, "deflection.png")
        self.assertTrue(os.path.isfile(png))
        self.assertGreater(os.path.getsize(png), 1000)
        self.assertIn("frame 1 (t = 0.2 s)", out)
        self.assertIn("3 mm at (0.5, 0, 0.5)", out)
        status, out, err = run_main([self.pvd, "--frame", "last", "--component", "magnitude", "-o",
                                     os.path.join(self.dir, "last.png"), "--title", "last frame"])
        self.assertEqual(status, 0, err)
        self.assertIn("frame 2", out)
        self.assertGreater(os.path.getsize(os.path.join(self.dir, "last.png")), 1000)

    def test_deformed_points_are_taken_back_to_the_reference(self):
        # shellflow's shell-run frames hold Points = reference + displacement (and a director).
        u = bump(self.points, 50.0)
        director = np.tile([0.0, 1.0, 0.0], (len(self.points), 1))
        write_vtu(os.path.join(self.dir, "shell_000003.vtu"), self.points + u, self.cells, self.type,
                  {"displacement": u, "director": director}, time=0.4)
        frames = psf.read_pvd(self.pvd) + [(0.4, os.path.join(self.dir, "shell_000003.vtu"))]
        first = psf.read_vtu(frames[0][1])
        deformed = psf.read_vtu(frames[3][1])
        np.testing.assert_allclose(psf.set_reference_points(deformed, first), self.points, atol=1e-15)
        alone = psf.read_vtu(frames[3][1])
        np.testing.assert_allclose(psf.set_reference_points(alone), self.points, atol=1e-15)
        self.assertEqual(psf.select_frame(frames)[0], 3)

    def test_unknown_array_is_one_line_naming_the_arrays(self):
        status, _, err = run_main([self.pvd, "--array", "pressure"])
        self.assertEqual(status, 1)
        self.assertEqual(len(err.strip().splitlines()), 1, err)
        self.assertIn("no point array 'pressure'", err)
        self.assertIn("displacement", err)

    def test_missing_frame_file(self):
        os.remove(os.path.join(self.dir, "shell_000002.vtu"))
        status, _, err = run_main([self.pvd])
        self.assertEqual(status, 1)
        self.assertEqual(len(err.strip().splitlines()), 1, err)
        self.assertIn("shell_000002.vtu", err)


class Geometry(unittest.TestCase):
    def test_mean_normal_of_the_plane_y_0_is_plus_y(self):
        points, _, _ = grid_mesh()
        np.testing.assert_allclose(psf.mean_normal(points), [0.0, 1.0, 0.0], atol=1e-12)
        np.testing.assert_allclose(psf.mean_normal(points[::-1] * [1, 1, -1]), [0.0, 1.0, 0.0], atol=1e-12)
        self.assertEqual(psf.plane_axes(points), (0, 2))

    def test_mean_normal_of_a_tilted_plane(self):
        n = np.array([1.0, 2.0, -3.0]) / math.sqrt(14.0)
        e1 = np.cross(n, [0.0, 0.0, 1.0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(n, e1)
        rng = np.random.default_rng(1)
        st = rng.uniform(-1.0, 1.0, size=(50, 2))
        points = np.array([0.3, -0.2, 0.7]) + st[:, :1] * e1 + st[:, 1:] * e2
        # oriented so that the largest |component| (z, -3) is positive
        np.testing.assert_allclose(psf.mean_normal(points), -n, atol=1e-12)
        with self.assertRaises(psf.PlotError):
            psf.mean_normal(np.outer(np.linspace(0, 1, 5), [1.0, 2.0, 3.0]))  # collinear

    def test_sub_triangles_tile_every_cell(self):
        for order, per_cell in ((1, 1), (2, 4), (3, 9)):
            with tempfile.TemporaryDirectory() as tmp:
                points, cells, vtk_type = grid_mesh(order=order)
                path = os.path.join(tmp, "g.vtu")
                write_vtu(path, points, cells, vtk_type, {"displacement": bump(points, 1.0)})
                data = psf.read_vtu(path)
            tris = psf.sub_triangles(data)
            self.assertEqual(tris.shape, (8 * per_cell, 3))
            xy = points[:, [0, 2]]
            a, b, c = xy[tris[:, 0]], xy[tris[:, 1]], xy[tris[:, 2]]
            areas = 0.5 * np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
            # every sub-triangle is one lattice triangle: equal areas summing to the unit square
            np.testing.assert_allclose(areas, 1.0 / (8 * per_cell), rtol=1e-12)

    def test_components(self):
        values = np.array([[3.0, 4.0, 0.0], [0.0, -1.0, 0.0]])
        np.testing.assert_allclose(psf.component_values(values, "normal", [0.0, 1.0, 0.0]), [4.0, -1.0])
        np.testing.assert_allclose(psf.component_values(values, "magnitude"), [5.0, 1.0])
        np.testing.assert_allclose(psf.component_values(values, "x"), [3.0, 0.0])
        np.testing.assert_allclose(psf.component_values(values[:, :1], "value"), [3.0, 0.0])


class DamagedFiles(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        points, cells, vtk_type = grid_mesh()
        self.path = os.path.join(self.tmp.name, "shell_000000.vtu")
        write_vtu(self.path, points, cells, vtk_type, {"displacement": bump(points, 1.0)})
        with open(self.path, "rb") as f:
            self.bytes = f.read()

    def tearDown(self):
        self.tmp.cleanup()

    def assert_one_line_error(self, content, needle=None):
        with open(self.path, "wb") as f:
            f.write(content)
        status, out, err = run_main([self.path, "-o", os.path.join(self.tmp.name, "x.png")])
        self.assertNotEqual(status, 0, out)
        lines = err.strip().splitlines()
        self.assertEqual(len(lines), 1, err)
        self.assertTrue(lines[0].startswith("plot_shell_field: "), lines[0])
        self.assertIn(self.path, lines[0])
        if needle:
            self.assertIn(needle, lines[0])
        self.assertFalse(os.path.exists(os.path.join(self.tmp.name, "x.png")))

    def test_truncated_file(self):
        for keep in (len(self.bytes) - 200, len(self.bytes) // 2, self.bytes.index(b"_", self.bytes.index(
                b"<AppendedData")) + 4):
            self.assert_one_line_error(self.bytes[:keep], "truncated")

    def test_truncated_header(self):
        self.assert_one_line_error(self.bytes[:300])

    def test_node_index_out_of_range(self):
        data = psf.read_vtu(self.path)
        start = self.bytes.index(b"_", self.bytes.index(b"<AppendedData")) + 1
        offset = int(self.bytes.split(b'Name="connectivity" format="appended" offset="')[1].split(b'"')[0])
        at = start + offset + 8
        bad = self.bytes[:at] + np.int64(len(data.points)).tobytes() + self.bytes[at + 8:]
        self.assert_one_line_error(bad, "outside")

    def test_not_a_vtu(self):
        self.assert_one_line_error(b"time,w\n0,0\n", "not a VTK XML file")


class Modes(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        points, cells, vtk_type = grid_mesh()
        arrays = {}
        for k in range(1, 5):  # mode_04 first: the panels follow the numbers, not the file
            u = np.zeros_like(points)
            u[:, 1] = np.sin(math.pi * (5 - k) * points[:, 0]) * np.sin(math.pi * points[:, 2])
            arrays[f"mode_{5 - k:02}"] = u
        arrays["flutter_mode_re"] = bump(points, 1.0)
        arrays["flutter_mode_im"] = bump(points, -0.5)
        self.path = os.path.join(self.tmp.name, "shell_modes.vtu")
        write_vtu(self.path, points, cells, vtk_type, arrays)
        self.csv = os.path.join(self.tmp.name, "modes.csv")
        with open(self.csv, "w") as f:
            f.write("mode,frequency_hz,angular_frequency\n1,10.5,66\n2,21,132\n3,42,264\n4,84,528\n")

    def tearDown(self):
        self.tmp.cleanup()

    def test_one_panel_per_mode(self):
        data = psf.read_vtu(self.path)
        fig, axes = psf.modes_figure(data, frequencies=psf.read_frequencies(self.csv))
        self.assertEqual(len(axes), 6)
        self.assertEqual([ax.get_title() for ax in axes],
                         ["mode 1, f = 10.5 Hz", "mode 2, f = 21 Hz", "mode 3, f = 42 Hz", "mode 4, f = 84 Hz",
                          "flutter mode (real part)", "flutter mode (imaginary part)"])
        psf.plt.close(fig)
        fig, axes = psf.modes_figure(data, max_panels=4)
        self.assertEqual(len(axes), 4)
        self.assertEqual(axes[0].get_title(), "mode 1")
        psf.plt.close(fig)

    def test_main_writes_modes_png(self):
        status, out, err = run_main([self.path, "--modes", "--frequencies", self.csv, "--max-panels", "3"])
        self.assertEqual(status, 0, err)
        png = os.path.join(self.tmp.name, "modes.png")
        self.assertTrue(os.path.isfile(png))
        self.assertGreater(os.path.getsize(png), 1000)
        self.assertIn("3 panel(s)", out)

    def test_modes_need_mode_arrays(self):
        status, _, err = run_main([self.path, "--modes", "--frequencies", os.path.join(self.tmp.name, "none.csv")])
        self.assertEqual(status, 1)
        self.assertIn("none.csv", err)
        status, _, err = run_main([self.path])  # no displacement: a hint to use --modes
        self.assertEqual(status, 1)
        self.assertIn("--modes", err)


if __name__ == "__main__":
    unittest.main()
