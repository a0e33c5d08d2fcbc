#pragma once
// VTK XML unstructured-grid writer (`.vtu`, binary appended raw data).
//
// The writer knows nothing of shellflow's mesh classes: it takes flat views of points,
// cells (Gmsh element type + 0-based connectivity in Gmsh node order) and fields. It maps
// each Gmsh element type to its VTK cell type and permutes the nodes from Gmsh order to
// VTK order (see docs/output.md for the tables).
//
// File layout written (one Piece, every array in the appended block):
//
//   <VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian"
//            header_type="UInt64">
//     <UnstructuredGrid>
//       <FieldData> TimeValue (Float64, 1 tuple; only when a time is given) </FieldData>
//       <Piece NumberOfPoints=".." NumberOfCells="..">
//         <PointData> point fields </PointData>   <CellData> cell fields </CellData>
//         <Points> Float64 x 3 </Points>
//         <Cells> connectivity Int64, offsets Int64, types UInt8 </Cells>
//       </Piece>
//     </UnstructuredGrid>
//     <AppendedData encoding="raw">_[UInt64 nbytes][bytes]...[UInt64 nbytes][bytes]
//     </AppendedData>
//   </VTKFile>
//
// Files are written to a new `<path>.tmp` and renamed over `<path>` once complete
// (core/output_file.h), so a run that dies mid-write never leaves a truncated file where a
// readable one was, and a link named like the file is never written through.
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "shellflow/core/types.h"

namespace shellflow::io {

/// Cells of one Gmsh element type. `connectivity` holds `n * nodes_per_cell` 0-based point
/// indices, each cell's nodes in Gmsh order.
struct VtuCellBlock {
  int gmsh_type = 0;
  std::span<const Index> connectivity;
};

/// A named field: `components` values per point (or per cell), tuple after tuple
/// (x0 y0 z0 x1 y1 z1 ...). Written as Float64 with `NumberOfComponents = components`.
struct VtuField {
  std::string name;
  int components = 1;
  std::span<const double> values;
};

/// Everything one `.vtu` file holds. Non-owning: the spans must outlive `write_vtu`.
struct VtuGrid {
  /// Point coordinates x0 y0 z0 x1 y1 z1 ... (use `flat()` to view a span of Vec3).
  std::span<const double> points;
  /// Cell blocks, written in this order; cell fields follow the same cell order.
  std::vector<VtuCellBlock> cells;
  std::vector<VtuField> point_fields;
  std::vector<VtuField> cell_fields;
  /// Simulation time, written as the FieldData array `TimeValue` that ParaView reads.
  std::optional<double> time;
};

/// Writes `grid` to `path` (parent directories are created). Throws shellflow::Error naming
/// the file and the offending block or field when the data are inconsistent (wrong sizes,
/// node index out of range, unsupported element type, duplicate or empty field name) or
/// when the file cannot be written; `path` is then left as it was.
void write_vtu(const std::filesystem::path& path, const VtuGrid& grid);

/// A point or cell array of the pieces a `.pvtu` joins (Float64, `components` per tuple).
struct PvtuArray {
  std::string name;
  int components = 1;
};

/// Writes the parallel file `path` (`.pvtu`) that joins the `.vtu` files `pieces` (paths
/// relative to its folder, '/' separated), each written by write_vtu with Float64 points and
/// the arrays `point_arrays` and `cell_arrays` in that order: ParaView opens it as one mesh.
/// Throws shellflow::Error when there is no piece or the file cannot be written.
void write_pvtu(const std::filesystem::path& path, const std::vector<std::string>& pieces,
                const std::vector<PvtuArray>& point_arrays, const std::vector<PvtuArray>& cell_arrays);

/// Views a span of Vec3 as the flat doubles x0 y0 z0 x1 ... (Vec3 holds exactly 3 doubles).
std::span<const double> flat(std::span<const Vec3> v);

// ---- Gmsh -> VTK cell mapping --------------------------------------------------------

/// Gmsh element types the writer handles: 15 point, 1 line2, 8 line3, 26 line4, 2 tri3,
/// 9 tri6, 21 tri10, 4 tet4, 11 tet10, 29 tet20.
bool is_vtu_supported_type(int gmsh_type);
/// Number of nodes of a supported Gmsh type; throws shellflow::InputError otherwise.
int gmsh_nodes_per_cell(int gmsh_type);
/// VTK cell type of a supported Gmsh type (VTK_VERTEX 1, VTK_LINE 3, VTK_QUADRATIC_EDGE 21,
/// VTK_LAGRANGE_CURVE 68, VTK_TRIANGLE 5, VTK_QUADRATIC_TRIANGLE 22,
/// VTK_LAGRANGE_TRIANGLE 69, VTK_TETRA 10, VTK_QUADRATIC_TETRA 24,
/// VTK_LAGRANGE_TETRAHEDRON 71); throws shellflow::InputError otherwise.
int vtk_cell_type(int gmsh_type);
/// Node permutation: VTK node i of a cell is Gmsh node `perm[i]` of the same cell.
/// Derived once by matching the two reference elements' node coordinates.
std::span<const int> gmsh_to_vtk_permutation(int gmsh_type);
/// Reference node coordinates, 3 per node, in Gmsh order and in Gmsh's own reference
/// element (lines on [-1, 1], triangles and tetrahedra on the unit simplex), as
/// `gmsh::model::mesh::getElementProperties` reports them.
std::span<const double> gmsh_reference_nodes(int gmsh_type);
/// Reference node coordinates, 3 per node, in VTK order and VTK's reference element
/// (lines on [0, 1], triangles and tetrahedra on the unit simplex).
std::span<const double> vtk_reference_nodes(int gmsh_type);

// ---- shared by the writers of this module ----------------------------------------------

/// Escapes &, <, >, " and ' for use inside an XML attribute value.
std::string xml_escape(std::string_view s);

}  // namespace shellflow::io
