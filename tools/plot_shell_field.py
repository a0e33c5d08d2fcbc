#!/usr/bin/env python3
"""Contour plots of a shell field from shellflow's VTK output (.pvd series or .vtu file).

usage: plot_shell_field.py INPUT [-o PNG] [--array NAME] [--component x|y|z|normal|magnitude]
                           [--frame largest|last|INDEX] [--modes] [--max-panels N]
                           [--frequencies CSV] [--title TEXT]
INPUT a .pvd (e.g. OUTDIR/shell.pvd): the frame with the largest |component| of the array
(default `displacement`; --frame last, or INDEX counted from 0 in the .pvd's order, negative
from the end), filled contours over the shell's reference configuration, in the plane of the
two largest extents of the reference points, the node of the largest |value| marked.
Default output: deflection.png next to INPUT (<array>.png for another array).
INPUT a .vtu: that one file. With --modes (e.g. OUTDIR/shell_modes.vtu): one panel per array
mode_NN (the first --max-panels, default 6; then flutter_mode_re / flutter_mode_im if present),
titled with the frequency of --frequencies modes.csv; default output modes.png next to INPUT.
--component normal (the default for 3-component arrays) is the component along the shell's
mean normal: the right singular vector of the smallest singular value of the centred reference
points, its largest Cartesian component made positive (+y for a plate in the plane y = 0).
A displacement is shown in mm, a velocity in m/s, a von Mises stress in MPa.
"""
import argparse
import csv
import math
import os
import re
import struct
import sys
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402
import numpy as np  # noqa: E402

PROG = "plot_shell_field"
COMPONENTS = ("x", "y", "z", "normal", "magnitude")
LEVELS = 21  # filled bands of a contour plot
PANEL_SIZE = (5.0, 4.0)  # inches per panel
MAX_COLUMNS = 3
STRETCH_MAX = 4.0  # a shell longer than this many times its width is drawn stretched across


class PlotError(Exception):
    """Bad input: main() prints it as one line and returns 1."""


# ---- reading ---------------------------------------------------------------------------

DTYPES = {"Float64": "f8", "Float32": "f4", "Int64": "i8", "Int32": "i4", "Int16": "i2", "Int8": "i1",
          "UInt64": "u8", "UInt32": "u4", "UInt16": "u2", "UInt8": "u1"}
MARKER = b'<AppendedData encoding="raw">'


class VtuData:
    """One VTK UnstructuredGrid piece: points (n, 3) as in the file, cells (connectivity, offsets,
    types), point_data {name: (n, components)}, time (the FieldData TimeValue, or None), path,
    and reference (n, 3): the reference coordinates the plots use, the points unless
    set_reference_points() found them deformed."""

    def __init__(self, path, points, connectivity, offsets, types, point_data, time):
        self.path = path
        self.points = points
        self.reference = points
        self.connectivity = connectivity
        self.offsets = offsets
        self.types = types
        self.point_data = point_data
        self.time = time


def read_vtu(path):
    """The VtuData of a .vtu written as shellflow writes it (one Piece, raw appended binary data,
    every array preceded by its byte count); raises PlotError naming the file when it cannot be
    read, is damaged (an array beyond the end of the file, sizes that disagree with the Piece's
    counts, node indices out of range) or uses a format this reader does not handle."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise PlotError(f"{path}: cannot read: {e.strerror or e}") from None
    try:
        return _parse_vtu(path, data)
    except PlotError:
        raise
    except (ValueError, KeyError, IndexError, TypeError, OverflowError, struct.error, ET.ParseError) as e:
        text = " ".join(str(e).split())
        raise PlotError(f"{path}: damaged or unsupported VTU file ({text})") from None


def _parse_vtu(path, data):
    def fail(message):
        raise PlotError(f"{path}: {message}")

    at = data.find(MARKER)
    if at < 0:
        if not data.lstrip().startswith(b"<"):
            fail("not a VTK XML file")
        fail("no raw appended data (<AppendedData encoding=\"raw\">): not a file written by shellflow, or truncated")
    underscore = data.find(b"_", at + len(MARKER))
    if underscore < 0 or data[at + len(MARKER):underscore].strip():
        fail("no '_' marker at the start of the appended data (damaged file)")
    start = underscore + 1
    try:
        root = ET.fromstring(data[:at].decode("utf-8") + "</VTKFile>")
    except (UnicodeDecodeError, ET.ParseError) as e:
        fail(f"unreadable XML header ({' '.join(str(e).split())})")
    if root.tag != "VTKFile" or root.get("type") != "UnstructuredGrid":
        fail(f"not a VTK UnstructuredGrid file (type '{root.get('type')}')")
    if root.get("compressor"):
        fail(f"compressed data ({root.get('compressor')}) are not supported")
    order = {"LittleEndian": "<", "BigEndian": ">"}.get(root.get("byte_order", "LittleEndian"))
    if order is None:
        fail(f"unknown byte_order '{root.get('byte_order')}'")
    header_type = root.get("header_type", "UInt32")
    if header_type not in ("UInt32", "UInt64"):
        fail(f"unsupported header_type '{header_type}'")
    header = np.dtype(order + DTYPES[header_type])
    pieces = root.findall("./UnstructuredGrid/Piece")
    if len(pieces) != 1:
        fail(f"{len(pieces)} pieces (expected one)")
    piece = pieces[0]
    try:
        n_points = int(piece.get("NumberOfPoints"))
        n_cells = int(piece.get("NumberOfCells"))
    except (TypeError, ValueError):
        fail("the Piece has no valid NumberOfPoints / NumberOfCells")
    if n_points < 0 or n_cells < 0:
        fail("negative NumberOfPoints / NumberOfCells")

    def array(element, what, count=None):
        """The values of a DataArray element, reshaped to (tuples, components) when count is given."""
        name = element.get("Name", "?")
        if element.get("format") != "appended":
            fail(f"{what} '{name}' is not in the appended data (format '{element.get('format')}')")
        kind = element.get("type")
        if kind not in DTYPES:
            fail(f"{what} '{name}' has the unsupported type '{kind}'")
        dtype = np.dtype(order + DTYPES[kind])
        try:
            offset = int(element.get("offset"))
            components = int(element.get("NumberOfComponents", "1"))
        except (TypeError, ValueError):
            fail(f"{what} '{name}' has no valid offset / NumberOfComponents")
        if offset < 0 or components < 1:
            fail(f"{what} '{name}' has offset {offset} and {components} components")
        at_size = start + offset
        if at_size + header.itemsize > len(data):
            fail(f"{what} '{name}' starts at byte {at_size}, beyond the end of the file "
                 f"({len(data)} bytes): truncated or damaged")
        size = int(np.frombuffer(data, header, 1, at_size)[0])
        if size % dtype.itemsize:
            fail(f"{what} '{name}' has {size} bytes, not a multiple of {dtype.itemsize} ({kind})")
        if at_size + header.itemsize + size > len(data):
            fail(f"{what} '{name}' needs bytes {at_size + header.itemsize}..{at_size + header.itemsize + size} "
                 f"but the file has {len(data)}: truncated or damaged")
        values = np.frombuffer(data, dtype, size // dtype.itemsize, at_size + header.itemsize)
        values = values.astype(dtype.newbyteorder("="))  # a writable native copy
        if count is not None:
            if values.size != count * components:
                fail(f"{what} '{name}' has {values.size} values, expected {count} x {components}")
            values = values.reshape(count, components)
        return values

    point_data = {}
    for element in piece.findall("./PointData/DataArray"):
        name = element.get("Name")
        if not name:
            fail("a point array has no name")
        point_data[name] = array(element, "point array", n_points).astype(float)
    points_element = piece.find("./Points/DataArray")
    if points_element is None:
        fail("no <Points>")
    points = array(points_element, "Points", n_points).astype(float)
    if points.shape[1] != 3:
        fail(f"Points have {points.shape[1]} components (expected 3)")
    if not np.all(np.isfinite(points)):
        fail("Points have non-finite coordinates")
    cells = {e.get("Name"): e for e in piece.findall("./Cells/DataArray")}
    for name in ("connectivity", "offsets", "types"):
        if name not in cells:
            fail(f"no cell array '{name}'")
    connectivity = array(cells["connectivity"], "cell array").astype(np.int64)
    offsets = array(cells["offsets"], "cell array").astype(np.int64)
    types = array(cells["types"], "cell array").astype(np.int64)
    if offsets.size != n_cells or types.size != n_cells:
        fail(f"{offsets.size} cell offsets and {types.size} cell types for {n_cells} cells")
    if n_cells and (offsets[0] < 0 or np.any(np.diff(offsets) < 0) or offsets[-1] != connectivity.size):
        fail("cell offsets are not increasing up to the connectivity's length")
    if connectivity.size and (connectivity.min() < 0 or connectivity.max() >= n_points):
        fail(f"cell connectivity refers to points outside 0..{n_points - 1}")
    time = None
    for element in root.findall("./UnstructuredGrid/FieldData/DataArray"):
        if element.get("Name") == "TimeValue" and (element.text or "").strip():
            time = float(element.text.split()[0])
    return VtuData(path, points, connectivity, offsets, types, point_data, time)


def read_pvd(path):
    """[(time, file path), ...] of a .pvd collection, in its order (file names relative to the
    .pvd's folder); raises PlotError when it cannot be read or lists no data set."""
    try:
        root = ET.parse(path).getroot()
    except OSError as e:
        raise PlotError(f"{path}: cannot read: {e.strerror or e}") from None
    except ET.ParseError as e:
        raise PlotError(f"{path}: not a readable .pvd ({e})") from None
    folder = os.path.dirname(path)
    frames = []
    for k, element in enumerate(root.iter("DataSet")):
        name = element.get("file")
        try:
            time = float(element.get("timestep", "nan"))
        except ValueError:
            raise PlotError(f"{path}: data set {k} has the timestep '{element.get('timestep')}'") from None
        if not name:
            raise PlotError(f"{path}: data set {k} has no file")
        frames.append((time, os.path.join(folder, name)))
    if not frames:
        raise PlotError(f"{path}: lists no data sets")
    return frames


def read_frequencies(path):
    """Frequencies [Hz] in the row order of a CSV: the column 'frequency_hz', or else the first
    whose name contains 'frequency'."""
    try:
        with open(path, newline="") as f:
            rows = [r for r in csv.reader(f) if r and not r[0].lstrip().startswith("#")]
    except OSError as e:
        raise PlotError(f"{path}: cannot read: {e.strerror or e}") from None
    header = [h.strip() for h in rows[0]] if rows else []
    if "frequency_hz" in header:
        col = header.index("frequency_hz")
    else:
        col = next((i for i, h in enumerate(header) if "frequency" in h.lower()), None)
        if col is None:
            raise PlotError(f"{path}: no frequency column (header: {','.join(header) or 'none'})")
    try:
        return [float(r[col]) for r in rows[1:]]
    except (ValueError, IndexError):
        raise PlotError(f"{path}: column '{header[col]}' is not a column of numbers") from None


# ---- geometry --------------------------------------------------------------------------

# Sub-triangles of each supported VTK triangle, as local node indices in VTK's order.
# VTK_LAGRANGE_TRIANGLE 69 (10 nodes): corners (0,0) (1,0) (0,1); edge (0,1) nodes at 1/3, 2/3;
# edge (1,2) at (2/3,1/3) (1/3,2/3); edge (2,0) at (0,2/3) (0,1/3); centre (1/3,1/3)
# (src/shellflow/io/vtu_writer.cpp). Lattice point (i, j) sits at (i/3, j/3).
_CUBIC_LATTICE = {(0, 0): 0, (3, 0): 1, (0, 3): 2, (1, 0): 3, (2, 0): 4, (2, 1): 5, (1, 2): 6,
                  (0, 2): 7, (0, 1): 8, (1, 1): 9}


def _cubic_sub_triangles():
    L = _CUBIC_LATTICE
    tris = []
    for j in range(3):
        for i in range(3 - j):
            tris.append((L[i, j], L[i + 1, j], L[i, j + 1]))  # pointing up
            if i + j <= 1:
                tris.append((L[i + 1, j], L[i + 1, j + 1], L[i, j + 1]))  # pointing down
    return tris


SUB_TRIANGLES = {
    5: (3, [(0, 1, 2)]),
    22: (6, [(0, 3, 5), (3, 1, 4), (5, 4, 2), (3, 4, 5)]),  # mid-edge nodes 3 (0-1), 4 (1-2), 5 (2-0)
    69: (10, _cubic_sub_triangles()),
}


def sub_triangles(data):
    """(m, 3) point indices: every triangle cell (VTK types 5, 22, 69) split into the linear
    triangles of its node lattice (1, 4, 9); other cells (lines, vertices) are ignored."""
    out = []
    for vtk_type, (nodes, local) in SUB_TRIANGLES.items():
        cells = np.flatnonzero(data.types == vtk_type)
        if cells.size == 0:
            continue
        starts = data.offsets[cells] - nodes
        counts = data.offsets[cells] - np.concatenate(([0], data.offsets))[cells]
        if np.any(counts != nodes):
            raise PlotError(f"{data.path}: a cell of VTK type {vtk_type} does not have {nodes} nodes")
        conn = data.connectivity[starts[:, None] + np.arange(nodes)[None, :]]
        out.append(conn[:, np.array(local)].reshape(-1, 3))
    if not out:
        found = sorted(set(int(t) for t in data.types))
        raise PlotError(f"{data.path}: no triangle cells (VTK types 5, 22, 69) to plot; cell types: {found}")
    return np.concatenate(out)


def mean_normal(points):
    """Unit mean normal of a roughly flat point cloud: the right singular vector of the smallest
    singular value of the centred points, oriented so that its largest |component| is positive."""
    points = np.asarray(points, dtype=float)
    if points.shape[0] < 3:
        raise PlotError("fewer than 3 points: no mean normal")
    centred = points - points.mean(axis=0)
    _, s, vt = np.linalg.svd(centred, full_matrices=False)
    if s[1] <= 1e-12 * max(s[0], 1e-300):
        raise PlotError("the points are collinear: no mean normal")
    n = vt[-1] / np.linalg.norm(vt[-1])
    if n[np.argmax(np.abs(n))] < 0:
        n = -n
    return n


def set_reference_points(data, first=None):
    """Sets data.reference to the reference coordinates and returns them. shellflow's shell-run
    frames (src/shellflow/run/mesh_outputs.cpp, ShellOutput::write) hold the DEFORMED positions
    as Points (reference + displacement), its initial frame and mode files the reference ones.
    With `first` (frame 0 of the same .pvd, written at rest): the Points are the reference when
    they equal first's, deformed when Points - displacement equals first's Points. Without it:
    deformed when the file holds the arrays `displacement` and `director` (a shell-run frame)."""
    disp = data.point_data.get("displacement")
    if disp is None or disp.shape != data.points.shape:
        data.reference = data.points
        return data.reference
    deformed = data.points - disp
    if first is not None and first.points.shape == data.points.shape:
        tol = 1e-9 * max(float(np.max(np.ptp(first.points, axis=0))), 1e-300)
        if np.max(np.abs(data.points - first.points)) <= tol:
            data.reference = data.points
        elif np.max(np.abs(deformed - first.points)) <= tol:
            data.reference = deformed
        else:
            data.reference = deformed if "director" in data.point_data else data.points
    else:
        data.reference = deformed if "director" in data.point_data else data.points
    return data.reference


def plane_axes(points):
    """Indices (a, b), a < b, of the two Cartesian axes along which the points extend most."""
    extent = np.ptp(np.asarray(points, dtype=float), axis=0)
    a, b = sorted(np.argsort(-extent, kind="stable")[:2])
    return int(a), int(b)


def component_values(values, component, normal=None):
    """1-D array of one component of a point array (n, c): x|y|z, normal (along the unit vector
    `normal`), magnitude, or value (a 1-component array as it is)."""
    values = np.asarray(values, dtype=float)
    if values.ndim == 1:
        values = values[:, None]
    if values.shape[1] == 1 and component in ("value", "magnitude"):
        return np.abs(values[:, 0]) if component == "magnitude" else values[:, 0]
    if component == "value":
        raise PlotError(f"a {values.shape[1]}-component array has no single value: choose a component")
    if component == "magnitude":
        return np.linalg.norm(values, axis=1)
    if values.shape[1] != 3:
        raise PlotError(f"a {values.shape[1]}-component array has no component '{component}' "
                        "(x, y, z and normal need 3 components; a scalar is drawn as it is, or as its magnitude)")
    if component == "normal":
        return values @ np.asarray(normal, dtype=float)
    return values[:, "xyz".index(component)]


def peak(values):
    """(node index, value) of the largest |value| (the first one of ties)."""
    k = int(np.argmax(np.abs(values)))
    return k, float(values[k])


# ---- frames ----------------------------------------------------------------------------

def frame_choice(text):
    """argparse type of --frame: 'largest', 'last' or an integer."""
    if text in ("largest", "last"):
        return text
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not largest, last or a frame index") from None


def frame_field(data, array, component, normal=None):
    """1-D values of `component` of `array` in a VtuData, checked; the normal component along
    `normal`, by default the mean normal of data.reference."""
    if array not in data.point_data:
        names = ", ".join(data.point_data) or "none"
        hint = "; use --modes for mode shapes" if any(re.fullmatch(r"mode_\d+", n) for n in data.point_data) else ""
        raise PlotError(f"{data.path}: no point array '{array}' (arrays: {names}){hint}")
    try:
        if component == "normal" and normal is None:
            normal = mean_normal(data.reference)
        return component_values(data.point_data[array], component, normal)
    except PlotError as e:
        raise PlotError(f"{data.path}: '{array}': {e}") from None


def frame_normal(data):
    """mean_normal of data.reference, its error naming the file."""
    try:
        return mean_normal(data.reference)
    except PlotError as e:
        raise PlotError(f"{data.path}: {e}") from None


def default_component(data, array):
    """normal for a 3-component array, value for a scalar, magnitude otherwise."""
    components = data.point_data[array].shape[1] if array in data.point_data else 3
    return "normal" if components == 3 else "value" if components == 1 else "magnitude"


def field_name(array, component):
    return array if component == "value" else f"{array} {component}"


def select_frame(frames, array="displacement", component="normal", choice="largest"):
    """(index, largest |value|) of the chosen frame of [(time, path), ...]: the one with the largest
    |component| of `array` over its points ('largest', the first one of ties; frames with
    non-finite values are passed over), the last one ('last') or frames[choice] (an int,
    negative from the end). The value is in the array's own units (m for a displacement). The
    normal component is along the mean normal of frame 0's reference points in every frame."""
    first = read_vtu(frames[0][1])
    normal = None
    if component == "normal":
        set_reference_points(first)
        normal = frame_normal(first)

    def largest(index):
        data = first if index == 0 else read_vtu(frames[index][1])
        if component == "normal":
            set_reference_points(data, first)
        return frame_field(data, array, component, normal)

    if isinstance(choice, int) or choice == "last":
        index = len(frames) - 1 if choice == "last" else choice
        if not -len(frames) <= index < len(frames):
            raise PlotError(f"frame {index} does not exist: the series has {len(frames)} frames (0..{len(frames) - 1})")
        index %= len(frames)
        return index, float(np.max(np.abs(largest(index))))
    if choice != "largest":
        raise PlotError(f"unknown frame choice '{choice}'")
    best, best_value, skipped = None, -1.0, 0
    for k in range(len(frames)):
        values = largest(k)
        if not np.all(np.isfinite(values)):
            skipped += 1
            continue
        value = float(np.max(np.abs(values))) if values.size else 0.0
        if value > best_value:
            best, best_value = k, value
    if best is None:
        raise PlotError(f"every frame has non-finite values of '{array}'")
    if skipped:
        print(f"{PROG}: note: passed over {skipped} frame(s) with non-finite values of '{array}'", file=sys.stderr)
    return best, best_value


# ---- drawing ---------------------------------------------------------------------------

def units(array):
    """(factor, unit) of the plotted values of an array (SI values times factor)."""
    if array == "displacement":
        return 1e3, "mm"
    if array == "velocity":
        return 1.0, "m/s"
    if array.startswith("von_mises"):
        return 1e-6, "MPa"
    return 1.0, ""


def contour_panel(fig, ax, data, values, title, label, unit_text, sequential=False):
    """Filled contours of `values` (one per point, already scaled to display units) over the
    shell's reference points, the node of the largest |value| marked: a diverging colour map
    symmetric about 0, or a sequential one from 0 when `sequential` (values >= 0); returns the
    (node index, value) of the largest |value|."""
    a, b = plane_axes(data.reference)
    x, y = data.reference[:, a], data.reference[:, b]
    if not np.all(np.isfinite(values)):
        raise PlotError(f"{data.path}: '{label}' has non-finite values")
    tri = mtri.Triangulation(x, y, sub_triangles(data))
    k, vk = peak(values)
    vmax = abs(vk)
    if sequential and np.all(values >= 0):
        cmap, levels = "viridis", np.linspace(0.0, vmax if vmax > 0 else 1.0, LEVELS + 1)
    else:
        span = vmax if vmax > 0 else 1.0
        cmap, levels = "RdBu_r", np.linspace(-span, span, LEVELS + 1)
    filled = ax.tricontourf(tri, values, levels=levels, cmap=cmap, extend="neither")
    if vmax > 0:
        for marker, mew in (("o", 1.3), ("+", 1.0)):
            ax.plot([x[k]], [y[k]], marker=marker, ms=7, mfc="none", mec="k", mew=mew, ls="none", clip_on=False)
    ax.set_xlabel(f"{'xyz'[a]} [m]")
    ax.set_ylabel(f"{'xyz'[b]} [m]")
    ex, ey = np.ptp(x), np.ptp(y)
    stretch = drawn_stretch(ex, ey)
    if stretch == 1.0:
        ax.set_aspect("equal")
    elif ey < ex:  # the short side drawn `stretch` times longer than to scale
        ax.set_aspect(stretch)
        ax.set_ylabel(f"{'xyz'[b]} [m] (stretched \u00d7{stretch:.3g})")
    else:
        ax.set_aspect(1.0 / stretch)
        ax.set_xlabel(f"{'xyz'[a]} [m] (stretched \u00d7{stretch:.3g})")
    ax.margins(0)
    # A colour bar as tall as the drawn (fixed-aspect) axes.
    box = ax.get_position()  # inches of the panel: the bar 0.15 in wide, 0.12 in from the axes
    width_in = max(box.width * fig.get_figwidth(), 1e-3)
    cax = ax.inset_axes([1.0 + 0.12 / width_in, 0.0, 0.15 / width_in, 1.0])
    bar = fig.colorbar(filled, cax=cax)
    bar.set_label(f"{label} [{unit_text}]" if unit_text else label)
    drawn_ratio = (ex / ey / stretch if ey < ex else ex * stretch / ey) if ex > 0 and ey > 0 else 1.0
    height_in = min(box.height * fig.get_figheight(), width_in / drawn_ratio)  # of the drawn axes
    bar.locator = matplotlib.ticker.MaxNLocator(max(3, min(7, int(height_in * 2.5))))
    bar.update_ticks()
    ax.set_title(title, fontsize=10)
    return k, vk


def drawn_stretch(ex, ey):
    """1, or the factor the short side of an ex x ey shell is drawn longer than to scale so that
    its drawn length-to-width ratio is at most STRETCH_MAX."""
    if ex > 0 and ey > 0 and max(ex, ey) / min(ex, ey) > STRETCH_MAX:
        return max(ex, ey) / min(ex, ey) / STRETCH_MAX
    return 1.0


def panel_size(points):
    """(width, height) [in] of a panel: PANEL_SIZE, made lower for a shell drawn wide and flat."""
    a, b = plane_axes(points)
    ex, ey = np.ptp(points[:, a]), np.ptp(points[:, b])
    w, h = PANEL_SIZE
    if ex > 0 and ey > 0 and ex > ey:
        drawn_ratio = ex / (ey * drawn_stretch(ex, ey))  # width / height of the drawn shell
        h = min(h, max(1.8, (w - 1.3) / drawn_ratio + 1.2))  # room for the colour bar, labels, title
    return w, h


def field_figure(data, array, component, time, title=None, normal=None):
    """Figure of one field (one panel) over data.reference; returns (fig, ax, node index of the
    largest |value|, its value in SI units). The normal component is along `normal`, by default
    the mean normal of data.reference."""
    values = frame_field(data, array, component, normal)
    factor, unit = units(array)
    name = field_name(array, component)
    w, h = panel_size(data.reference)
    fig, ax = plt.subplots(figsize=(w + 1.0, h + 0.6))
    sequential = component == "magnitude" or array.startswith("von_mises")
    k, _ = contour_panel(fig, ax, data, values * factor, "", name, unit, sequential)
    where = point_text(data.reference, k)
    when = f" at t = {time:.6g} s" if time is not None and math.isfinite(time) else ""
    ax.set_title(title or (f"{name}{when}\n(largest |value| {abs(values[k]) * factor:.4g}"
                           f"{' ' + unit if unit else ''} at {where})"), fontsize=10)
    fig.tight_layout()
    return fig, ax, k, float(values[k])


def point_text(points, k):
    """'(x, y, z)' of point k, 4 digits, round-off below 1e-9 of the shell's size shown as 0."""
    size = float(np.max(np.ptp(points, axis=0))) if len(points) else 0.0
    return "(" + ", ".join(f"{(0.0 if abs(c) <= 1e-9 * size else c):.4g}" for c in points[k]) + ")"


def mode_arrays(data):
    """[(array name, panel title), ...]: mode_NN in number order, then flutter_mode_re/_im."""
    modes = sorted((int(m.group(1)), name) for name in data.point_data
                   for m in [re.fullmatch(r"mode_(\d+)", name)] if m)
    out = [(name, f"mode {number}") for number, name in modes]
    for name, title in (("flutter_mode_re", "flutter mode (real part)"),
                        ("flutter_mode_im", "flutter mode (imaginary part)")):
        if name in data.point_data:
            out.append((name, title))
    return out


def modes_figure(data, component="normal", max_panels=6, frequencies=None, title=None):
    """Figure with one panel per mode array (at most max_panels, <= 3 columns); returns
    (fig, panel axes)."""
    arrays = mode_arrays(data)[:max_panels]
    if not arrays:
        raise PlotError(f"{data.path}: no arrays mode_NN or flutter_mode_re/_im "
                        f"(arrays: {', '.join(data.point_data) or 'none'})")
    ncols = min(MAX_COLUMNS, len(arrays))
    nrows = math.ceil(len(arrays) / ncols)
    w, h = panel_size(data.reference)
    fig, axes = plt.subplots(nrows, ncols, figsize=(w * ncols, h * nrows + (0.4 if title else 0.0)), squeeze=False)
    axes = axes.ravel()
    for ax in axes[len(arrays):]:
        ax.remove()
    for ax, (name, panel_title) in zip(axes, arrays):
        m = re.fullmatch(r"mode_(\d+)", name)
        if m and frequencies is not None and 1 <= int(m.group(1)) <= len(frequencies):
            panel_title += f", f = {frequencies[int(m.group(1)) - 1]:.5g} Hz"
        values = frame_field(data, name, component)
        contour_panel(fig, ax, data, values, panel_title, f"{component} component", "", component == "magnitude")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig, list(axes[:len(arrays)])


# ---- command line ----------------------------------------------------------------------

def run(args):
    """Draws and writes the figure; returns (output path, one-line summary)."""
    is_pvd = args.input.lower().endswith(".pvd")
    folder = os.path.dirname(args.input)
    if args.modes:
        if is_pvd:
            raise PlotError(f"{args.input}: --modes needs a .vtu with arrays mode_NN (e.g. shell_modes.vtu)")
        if args.array:
            raise PlotError("--array cannot be combined with --modes (every mode_NN array is drawn)")
        if args.max_panels < 1:
            raise PlotError(f"--max-panels {args.max_panels}: must be at least 1")
        frequencies = read_frequencies(args.frequencies) if args.frequencies else None
        data = read_vtu(args.input)
        fig, axes = modes_figure(data, args.component or "normal", args.max_panels, frequencies, args.title)
        output = args.output or os.path.join(folder, "modes.png")
        summary = f"{len(axes)} panel(s)"
    else:
        array = args.array or "displacement"
        if is_pvd:
            frames = read_pvd(args.input)
        else:
            frames = [(None, args.input)]
        first = read_vtu(frames[0][1])
        if array not in first.point_data:
            frame_field(first, array, "x")  # raises the error that lists the arrays
        component = args.component or default_component(first, array)
        if component == "value" or first.point_data[array].shape[1] == 1 and component != "magnitude":
            component = "value"  # a scalar array: --component x|y|z|normal mean the value itself
        index = select_frame(frames, array, component, args.frame)[0] if is_pvd else 0
        set_reference_points(first)
        normal = frame_normal(first) if component == "normal" else None
        data = first if index == 0 else read_vtu(frames[index][1])
        if index != 0:
            set_reference_points(data, first)
        time = frames[index][0] if is_pvd else data.time
        fig, _, k, value = field_figure(data, array, component, time, args.title, normal)
        default = "deflection.png" if array == "displacement" else f"{array}.png"
        output = args.output or os.path.join(folder, default)
        factor, unit = units(array)
        where = point_text(data.reference, k)
        when = f"t = {time:.6g} s" if time is not None and math.isfinite(time) else ""
        frame = (f"frame {index}" + (f" ({when})" if when else "")) if is_pvd else (when or "no time")
        summary = (f"{frame}, largest |{field_name(array, component)}| {abs(value) * factor:.4g}"
                   f"{' ' + unit if unit else ''} at {where}")
    try:
        fig.savefig(output, dpi=120)
    except OSError as e:
        raise PlotError(f"cannot write {output}: {e.strerror or e}") from None
    finally:
        plt.close(fig)
    return output, summary


def main(argv=None):
    ap = argparse.ArgumentParser(prog="plot_shell_field.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("input", help=".pvd series or .vtu file of the shell")
    ap.add_argument("-o", "--output", help="PNG (default: deflection.png or modes.png next to INPUT)")
    ap.add_argument("--array", help="point array (default: displacement)")
    ap.add_argument("--component", choices=COMPONENTS,
                    help="component drawn (default: normal for 3 components)")
    ap.add_argument("--frame", type=frame_choice, default="largest",
                    help="frame of a .pvd: largest (default), last or an index from 0 (negative: from the end)")
    ap.add_argument("--modes", action="store_true", help="one panel per mode_NN array of a .vtu")
    ap.add_argument("--max-panels", type=int, default=6, help="modes drawn with --modes (default 6)")
    ap.add_argument("--frequencies", help="modes.csv: frequencies in the panel titles (--modes)")
    ap.add_argument("--title", help="title of the figure (replaces the default)")
    args = ap.parse_args(sys.argv[1:] if argv is None else argv)
    try:
        output, summary = run(args)
    except PlotError as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 1
    except (ValueError, RuntimeError) as e:  # matplotlib on a degenerate mesh, e.g. all points on a line
        print(f"{PROG}: {args.input}: cannot plot: {' '.join(str(e).split())}", file=sys.stderr)
        return 1
    print(f"{PROG}: wrote {output}: {summary}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
