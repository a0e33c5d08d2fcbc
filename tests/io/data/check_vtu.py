"""Independent check of a .vtu written by tests/io/test_vtu_writer.cpp.

Usage: check_vtu.py FILE:GMSH_TYPE[,GMSH_TYPE...] [FILE:...]

Each file holds one cell per Gmsh type given, in that order. Cell c's nodes sit at
F_c(xi) for the node's reference position xi, with F_c the curved map below (the C++ test
places Gmsh-ordered nodes with Gmsh's reference positions, taken from the Gmsh API). This
script checks, against VTK's own reference positions (typed in from VTK's sources), that
VTK node i of each cell sits at F_c(xi_i^VTK): i.e. that the writer permuted the nodes from
Gmsh order to VTK order. It reads the file twice: with meshio, and with a minimal parser of
the raw appended block (header type, array types, byte counts, offsets).

Prints what differs and exits 1 on any mismatch.
"""
import struct
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np

T1, T2 = 1.0 / 3.0, 2.0 / 3.0
# VTK reference positions, in VTK point order.
VTK_REF = {
    # vtkVertex, vtkLine, vtkQuadraticEdge (pcoords 0, 1, 0.5), vtkLagrangeCurve order 3
    15: [(0, 0, 0)],
    1: [(0, 0, 0), (1, 0, 0)],
    8: [(0, 0, 0), (1, 0, 0), (0.5, 0, 0)],
    26: [(0, 0, 0), (1, 0, 0), (T1, 0, 0), (T2, 0, 0)],
    # vtkTriangle, vtkQuadraticTriangle, vtkLagrangeTriangle order 3
    2: [(0, 0, 0), (1, 0, 0), (0, 1, 0)],
    9: [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0.5, 0, 0), (0.5, 0.5, 0), (0, 0.5, 0)],
    21: [(0, 0, 0), (1, 0, 0), (0, 1, 0),
         (T1, 0, 0), (T2, 0, 0), (T2, T1, 0), (T1, T2, 0), (0, T2, 0), (0, T1, 0),
         (T1, T1, 0)],
    # vtkTetra, vtkQuadraticTetra, vtkLagrangeTetra order 3
    4: [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)],
    11: [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1),
         (0.5, 0, 0), (0.5, 0.5, 0), (0, 0.5, 0), (0, 0, 0.5), (0.5, 0, 0.5), (0, 0.5, 0.5)],
    29: [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1),
         (T1, 0, 0), (T2, 0, 0),    # edge (0,1)
         (T2, T1, 0), (T1, T2, 0),  # edge (1,2)
         (0, T2, 0), (0, T1, 0),    # edge (2,0)
         (0, 0, T1), (0, 0, T2),    # edge (0,3)
         (T2, 0, T1), (T1, 0, T2),  # edge (1,3)
         (0, T2, T1), (0, T1, T2),  # edge (2,3)
         (T1, 0, T1),               # face (0,1,3)
         (T1, T1, T1),              # face (1,2,3)
         (0, T1, T1),               # face (2,0,3)
         (T1, T1, 0)],              # face (0,2,1)
}
VTK_TYPE = {15: 1, 1: 3, 8: 21, 26: 68, 2: 5, 9: 22, 21: 69, 4: 10, 11: 24, 29: 71}
MESHIO_NAME = {1: "vertex", 3: "line", 21: "line3", 68: "VTK_LAGRANGE_CURVE",
               5: "triangle", 22: "triangle6", 69: "VTK_LAGRANGE_TRIANGLE",
               10: "tetra", 24: "tetra10", 71: "VTK_LAGRANGE_TETRAHEDRON"}
ODD_NAME = "a<b>&\"c'd"

A = np.array([[1.0, 0.3, 0.2], [0.1, 1.2, 0.4], [-0.2, 0.1, 0.9]])


def F(c, xi):
    """Curved map of cell c (same recipe as place_node() in test_vtu_writer.cpp)."""
    x0, x1, x2 = xi
    b = np.array([2.0 * c, -1.0 * c, 0.5 * c])
    q = np.array([x1 * x2, x0 * x2 + x0 * x0, x0 * x1 - x1 * x1])
    return b + A @ np.array(xi, dtype=float) + 0.15 * q


def point_fields(x):
    px, py, pz = x
    s = px + 2.0 * py - 3.0 * pz + px * py
    return {"pressure": [s], "velocity": [py, -px, px * pz], "pair": [px, pz],
            ODD_NAME: [s + 1.0]}


errors = []


def check(cond, msg):
    if not cond:
        errors.append(msg)


def close(a, b, tol=1e-12):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return a.shape == b.shape and np.allclose(a, b, rtol=tol, atol=tol)


def check_meshio(path, types):
    m = meshio.read(path)
    n_nodes = sum(len(VTK_REF[t]) for t in types)
    check(m.points.shape == (n_nodes, 3), f"points shape {m.points.shape}, expected ({n_nodes}, 3)")
    check(len(m.cells) == len(types), f"{len(m.cells)} cell blocks, expected {len(types)}")
    used = []
    for c, (block, t) in enumerate(zip(m.cells, types)):
        name = MESHIO_NAME[VTK_TYPE[t]]
        check(block.type == name, f"cell {c}: type {block.type}, expected {name}")
        ref = VTK_REF[t]
        check(block.data.shape == (1, len(ref)), f"cell {c}: shape {block.data.shape}")
        if block.data.shape != (1, len(ref)):
            continue
        for i, p in enumerate(block.data[0]):
            used.append(int(p))
            want = F(c, ref[i])
            check(close(m.points[p], want),
                  f"cell {c} (Gmsh type {t}) VTK node {i}: point {p} at {m.points[p]}, "
                  f"expected {want} (reference {ref[i]})")
    check(sorted(used) == list(range(n_nodes)), "points are not each used exactly once")
    for p, x in enumerate(m.points):
        for name, want in point_fields(x).items():
            got = m.point_data.get(name)
            if got is None:
                check(False, f"point field {name!r} missing (have {list(m.point_data)})")
                continue
            got = np.asarray(got[p]).ravel()
            check(close(got, want), f"point field {name!r} at point {p}: {got}, expected {want}")
    for c in range(len(types)):
        cid = m.cell_data.get("cell id")
        cvec = m.cell_data.get("cell vec")
        if cid is None or cvec is None:
            check(False, f"cell fields missing (have {list(m.cell_data)})")
            break
        check(close(np.ravel(cid[c]), [c + 0.5]), f"cell id of cell {c}: {cid[c]}")
        check(close(np.ravel(cvec[c]), [c, 2.0 * c, -1.0 * c]), f"cell vec of cell {c}: {cvec[c]}")
    tv = m.field_data.get("TimeValue")
    check(tv is not None and np.ravel(tv).tolist() == [0.1],
          f"field data TimeValue {tv}, expected exactly [0.1]")


def check_raw(path, types):
    raw = open(path, "rb").read()
    tag = b'<AppendedData encoding="raw">'
    i = raw.find(tag)
    check(i >= 0, "no <AppendedData encoding=\"raw\"> element")
    if i < 0:
        return
    head = raw[:i].decode() + "</VTKFile>"
    root = ET.fromstring(head)
    check(root.get("type") == "UnstructuredGrid", f"VTKFile type {root.get('type')}")
    check(root.get("header_type") == "UInt64", f"header_type {root.get('header_type')}")
    check(root.get("byte_order") == "LittleEndian", f"byte_order {root.get('byte_order')}")
    underscore = raw.find(b"_", i + len(tag))
    check(raw[i + len(tag):underscore].strip() == b"", "junk before the '_' marker")
    data = raw[underscore + 1:]
    piece = root.find("UnstructuredGrid/Piece")
    n_points = int(piece.get("NumberOfPoints"))
    n_cells = int(piece.get("NumberOfCells"))
    check(n_cells == len(types), f"NumberOfCells {n_cells}")
    sizes = {"Float64": 8, "Int64": 8, "Int32": 4, "UInt8": 1}
    arrays = [a for a in root.iter("DataArray") if a.get("format") == "appended"]
    arrays.sort(key=lambda a: int(a.get("offset")))
    pos = 0
    decoded = {}
    for a in arrays:
        name = a.get("Name")
        check(int(a.get("offset")) == pos, f"array {name}: offset {a.get('offset')}, expected {pos}")
        pos = int(a.get("offset"))
        (nbytes,) = struct.unpack("<Q", data[pos:pos + 8])
        item = sizes[a.get("type")]
        body = data[pos + 8:pos + 8 + nbytes]
        check(len(body) == nbytes and nbytes % item == 0, f"array {name}: {nbytes} bytes")
        decoded[name] = (a, body)
        pos += 8 + nbytes
    check(data[pos:].split() == [b"</AppendedData>", b"</VTKFile>"],
          f"unexpected bytes after the last array: {data[pos:pos + 40]!r}")
    expect_type = {"Points": "Float64", "connectivity": "Int64", "offsets": "Int64",
                   "types": "UInt8"}
    for name, t in expect_type.items():
        check(name in decoded and decoded[name][0].get("type") == t, f"array {name} not {t}")
    if errors:
        return
    check(decoded["Points"][0].get("NumberOfComponents") == "3", "Points not 3 components")
    check(len(decoded["Points"][1]) == 24 * n_points, "Points byte count")
    types_arr = np.frombuffer(decoded["types"][1], dtype="<u1").tolist()
    check(types_arr == [VTK_TYPE[t] for t in types], f"VTK types {types_arr}")
    offsets = np.frombuffer(decoded["offsets"][1], dtype="<i8").tolist()
    check(offsets == np.cumsum([len(VTK_REF[t]) for t in types]).tolist(), f"offsets {offsets}")
    conn = np.frombuffer(decoded["connectivity"][1], dtype="<i8")
    check(len(conn) == offsets[-1], "connectivity length")
    for name, comps, count in [("pressure", 1, n_points), ("velocity", 3, n_points),
                               ("pair", 2, n_points), (ODD_NAME, 1, n_points),
                               ("cell id", 1, n_cells), ("cell vec", 3, n_cells)]:
        check(name in decoded, f"array {name!r} missing")
        if name in decoded:
            a, body = decoded[name]
            check(a.get("type") == "Float64", f"{name}: type {a.get('type')}")
            check(int(a.get("NumberOfComponents")) == comps, f"{name}: components")
            check(len(body) == 8 * comps * count, f"{name}: {len(body)} bytes")


def main():
    n_files = 0
    for arg in sys.argv[1:]:
        path, _, type_list = arg.rpartition(":")
        types = [int(t) for t in type_list.split(",")]
        before = len(errors)
        check_raw(path, types)
        try:
            check_meshio(path, types)
        except Exception as e:  # a file meshio cannot read is a mismatch too
            errors.append(f"meshio cannot read {path}: {type(e).__name__}: {e}")
        if len(errors) > before:
            errors.append(f"{len(errors) - before} mismatch(es) in {path} (types {types})")
        n_files += 1
    if errors:
        print("\n".join(errors[:60]))
        return 1
    print(f"OK: {n_files} file(s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
