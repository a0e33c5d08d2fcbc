#include "shellflow/io/vtu_writer.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <ostream>
#include <set>
#include <system_error>

#include "shellflow/core/error.h"
#include "shellflow/core/output_file.h"

namespace shellflow::io {
namespace {

// ---- reference elements ----------------------------------------------------------------
//
// Gmsh: node coordinates as gmsh::model::mesh::getElementProperties returns them (Gmsh
// 4.8; checked by tests/io/test_vtk_cell_map.cpp against the Gmsh API itself).
// VTK: parametric coordinates of the cell's points, from VTK's sources
// (vtkQuadraticEdge/Triangle/Tetra::GetParametricCoords, and the point ordering of
// vtkHigherOrderCurve/Triangle/Tetra: vertices, then edge points walking each edge from
// its first to its second vertex over the edges (0,1) (1,2) (2,0) (0,3) (1,3) (2,3), then
// face points over the faces (0,1,3) (1,2,3) (2,0,3) (0,2,1), then interior points).

constexpr double t1 = 1.0 / 3.0;
constexpr double t2 = 2.0 / 3.0;

struct CellKind {
  int gmsh_type;
  int vtk_type;
  int nodes;
  bool is_line;                  // Gmsh lines live on [-1, 1], VTK lines on [0, 1]
  std::vector<double> gmsh_ref;  // 3 per node
  std::vector<double> vtk_ref;   // 3 per node
  std::vector<int> perm;         // vtk node i = gmsh node perm[i]
};

std::vector<CellKind> make_cell_kinds() {
  std::vector<CellKind> k;
  // clang-format off
  k.push_back({15, 1, 1, false, {0, 0, 0}, {0, 0, 0}, {}});
  k.push_back({1, 3, 2, true, {-1, 0, 0,  1, 0, 0}, {0, 0, 0,  1, 0, 0}, {}});
  k.push_back({8, 21, 3, true, {-1, 0, 0,  1, 0, 0,  0, 0, 0},
                               {0, 0, 0,  1, 0, 0,  0.5, 0, 0}, {}});
  k.push_back({26, 68, 4, true, {-1, 0, 0,  1, 0, 0,  -t1, 0, 0,  t1, 0, 0},
                                {0, 0, 0,  1, 0, 0,  t1, 0, 0,  t2, 0, 0}, {}});
  k.push_back({2, 5, 3, false, {0, 0, 0,  1, 0, 0,  0, 1, 0},
                               {0, 0, 0,  1, 0, 0,  0, 1, 0}, {}});
  k.push_back({9, 22, 6, false,
               {0, 0, 0,  1, 0, 0,  0, 1, 0,  0.5, 0, 0,  0.5, 0.5, 0,  0, 0.5, 0},
               {0, 0, 0,  1, 0, 0,  0, 1, 0,  0.5, 0, 0,  0.5, 0.5, 0,  0, 0.5, 0}, {}});
  k.push_back({21, 69, 10, false,
               {0, 0, 0,  1, 0, 0,  0, 1, 0,
                t1, 0, 0,  t2, 0, 0,  t2, t1, 0,  t1, t2, 0,  0, t2, 0,  0, t1, 0,
                t1, t1, 0},
               {0, 0, 0,  1, 0, 0,  0, 1, 0,
                t1, 0, 0,  t2, 0, 0,      // edge (0,1)
                t2, t1, 0,  t1, t2, 0,    // edge (1,2)
                0, t2, 0,  0, t1, 0,      // edge (2,0)
                t1, t1, 0}, {}});         // interior
  k.push_back({4, 10, 4, false, {0, 0, 0,  1, 0, 0,  0, 1, 0,  0, 0, 1},
                                {0, 0, 0,  1, 0, 0,  0, 1, 0,  0, 0, 1}, {}});
  k.push_back({11, 24, 10, false,
               {0, 0, 0,  1, 0, 0,  0, 1, 0,  0, 0, 1,
                0.5, 0, 0,  0.5, 0.5, 0,  0, 0.5, 0,  0, 0, 0.5,  0, 0.5, 0.5,  0.5, 0, 0.5},
               {0, 0, 0,  1, 0, 0,  0, 1, 0,  0, 0, 1,
                0.5, 0, 0,  0.5, 0.5, 0,  0, 0.5, 0,  0, 0, 0.5,  0.5, 0, 0.5,  0, 0.5, 0.5},
               {}});
  k.push_back({29, 71, 20, false,
               {0, 0, 0,  1, 0, 0,  0, 1, 0,  0, 0, 1,
                t1, 0, 0,  t2, 0, 0,        // edge 0-1
                t2, t1, 0,  t1, t2, 0,      // edge 1-2
                0, t2, 0,  0, t1, 0,        // edge 2-0
                0, 0, t2,  0, 0, t1,        // edge 3-0
                0, t1, t2,  0, t2, t1,      // edge 3-2
                t1, 0, t2,  t2, 0, t1,      // edge 3-1
                t1, t1, 0,                  // face 0-2-1
                t1, 0, t1,                  // face 0-1-3
                0, t1, t1,                  // face 0-3-2
                t1, t1, t1},                // face 3-1-2
               {0, 0, 0,  1, 0, 0,  0, 1, 0,  0, 0, 1,
                t1, 0, 0,  t2, 0, 0,        // edge (0,1)
                t2, t1, 0,  t1, t2, 0,      // edge (1,2)
                0, t2, 0,  0, t1, 0,        // edge (2,0)
                0, 0, t1,  0, 0, t2,        // edge (0,3)
                t2, 0, t1,  t1, 0, t2,      // edge (1,3)
                0, t2, t1,  0, t1, t2,      // edge (2,3)
                t1, 0, t1,                  // face (0,1,3)
                t1, t1, t1,                 // face (1,2,3)
                0, t1, t1,                  // face (2,0,3)
                t1, t1, 0},                 // face (0,2,1)
               {}});
  // clang-format on

  // Match reference positions: VTK node i sits where Gmsh node perm[i] sits.
  for (auto& c : k) {
    const auto n = static_cast<std::size_t>(c.nodes);
    if (c.gmsh_ref.size() != 3 * n || c.vtk_ref.size() != 3 * n) {
      throw Error(fmt::format("internal: reference table of Gmsh type {} has the wrong size", c.gmsh_type));
    }
    std::vector<bool> used(n, false);
    c.perm.assign(n, -1);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < n; ++j) {
        double d = 0;
        for (std::size_t a = 0; a < 3; ++a) {
          double g = c.gmsh_ref[3 * j + a];
          if (c.is_line && a == 0) g = 0.5 * (g + 1.0);
          d = std::max(d, std::abs(g - c.vtk_ref[3 * i + a]));
        }
        if (d < 1e-12 && !used[j]) {
          used[j] = true;
          c.perm[i] = static_cast<int>(j);
          break;
        }
      }
      if (c.perm[i] < 0) {
        throw Error(fmt::format("internal: VTK node {} of Gmsh type {} matches no Gmsh node", i, c.gmsh_type));
      }
    }
  }
  return k;
}

const CellKind* find_kind(int gmsh_type) {
  static const std::vector<CellKind> kinds = make_cell_kinds();
  for (const auto& c : kinds) {
    if (c.gmsh_type == gmsh_type) return &c;
  }
  return nullptr;
}

const CellKind& kind(int gmsh_type) {
  const CellKind* c = find_kind(gmsh_type);
  if (c == nullptr) {
    throw_input_error(
        "element type {} (Gmsh numbering) cannot be written to VTK: supported types are "
        "15 point, 1/8/26 lines, 2/9/21 triangles, 4/11/29 tetrahedra",
        gmsh_type);
  }
  return *c;
}

// ---- writing ---------------------------------------------------------------------------

/// One array of the appended block: where its bytes are and how many.
struct Blob {
  const void* data;
  std::uint64_t bytes;
};

std::string double_text(double x) { return fmt::format("{:.17g}", x); }

void check_fields(const std::string& file, const std::vector<VtuField>& fields, std::size_t count, const char* where) {
  std::set<std::string> names;
  for (const auto& f : fields) {
    if (f.name.empty()) {
      throw Error(fmt::format("{}: a {} field has an empty name", file, where));
    }
    if (!names.insert(f.name).second) {
      throw Error(fmt::format("{}: two {} fields are named '{}'", file, where, f.name));
    }
    if (f.components < 1) {
      throw Error(
          fmt::format("{}: {} field '{}' has {} components (need at least 1)", file, where, f.name, f.components));
    }
    const std::size_t expected = count * static_cast<std::size_t>(f.components);
    if (f.values.size() != expected) {
      throw Error(
          fmt::format("{}: {} field '{}' has {} values, expected {} ({} {}s x {} "
                      "components)",
                      file, where, f.name, f.values.size(), expected, count, where, f.components));
    }
  }
}

}  // namespace

// ---- public: cell mapping --------------------------------------------------------------

bool is_vtu_supported_type(int gmsh_type) { return find_kind(gmsh_type) != nullptr; }
int gmsh_nodes_per_cell(int gmsh_type) { return kind(gmsh_type).nodes; }
int vtk_cell_type(int gmsh_type) { return kind(gmsh_type).vtk_type; }
std::span<const int> gmsh_to_vtk_permutation(int gmsh_type) { return kind(gmsh_type).perm; }
std::span<const double> gmsh_reference_nodes(int gmsh_type) { return kind(gmsh_type).gmsh_ref; }
std::span<const double> vtk_reference_nodes(int gmsh_type) { return kind(gmsh_type).vtk_ref; }

std::span<const double> flat(std::span<const Vec3> v) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be 3 packed doubles");
  if (v.empty()) return {};
  return {v.front().data(), 3 * v.size()};
}

// ---- public: helpers -------------------------------------------------------------------

std::string xml_escape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (char ch : s) {
    switch (ch) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += ch;
    }
  }
  return out;
}

// ---- public: the writer ----------------------------------------------------------------

void write_vtu(const std::filesystem::path& path, const VtuGrid& grid) {
  const std::string file = path.string();
  // 1. Check the input, so that nothing is written for inconsistent data.
  if (grid.points.size() % 3 != 0) {
    throw Error(fmt::format("{}: {} point coordinates is not a multiple of 3", file, grid.points.size()));
  }
  const std::size_t n_points = grid.points.size() / 3;
  std::size_t n_cells = 0;
  std::size_t n_conn = 0;
  for (std::size_t b = 0; b < grid.cells.size(); ++b) {
    const auto& block = grid.cells[b];
    const CellKind* c = find_kind(block.gmsh_type);
    if (c == nullptr) {
      throw Error(
          fmt::format("{}: cell block {} has Gmsh element type {}, which the VTU writer does not handle "
                      "(supported: 15, 1, 8, 26, 2, 9, 21, 4, 11, 29)",
                      file, b, block.gmsh_type));
    }
    const auto npc = static_cast<std::size_t>(c->nodes);
    if (block.connectivity.size() % npc != 0) {
      throw Error(
          fmt::format("{}: cell block {} (Gmsh type {}) has {} node indices, not a "
                      "multiple of {}",
                      file, b, block.gmsh_type, block.connectivity.size(), npc));
    }
    for (std::size_t i = 0; i < block.connectivity.size(); ++i) {
      const Index v = block.connectivity[i];
      if (v < 0 || static_cast<std::size_t>(v) >= n_points) {
        throw Error(
            fmt::format("{}: cell {} of block {} refers to point {}, but there are {} "
                        "points",
                        file, i / npc, b, v, n_points));
      }
    }
    n_cells += block.connectivity.size() / npc;
    n_conn += block.connectivity.size();
  }
  check_fields(file, grid.point_fields, n_points, "point");
  check_fields(file, grid.cell_fields, n_cells, "cell");
  if (grid.time && !std::isfinite(*grid.time)) {
    throw Error(fmt::format("{}: time {} is not finite", file, *grid.time));
  }

  // 2. Cell arrays in VTK order.
  std::vector<std::int64_t> connectivity;
  std::vector<std::int64_t> offsets;
  std::vector<std::uint8_t> types;
  connectivity.reserve(n_conn);
  offsets.reserve(n_cells);
  types.reserve(n_cells);
  for (const auto& block : grid.cells) {
    const CellKind& c = kind(block.gmsh_type);
    const auto npc = static_cast<std::size_t>(c.nodes);
    for (std::size_t e = 0; e < block.connectivity.size() / npc; ++e) {
      const Index* nodes = block.connectivity.data() + e * npc;
      for (std::size_t i = 0; i < npc; ++i) {
        connectivity.push_back(nodes[static_cast<std::size_t>(c.perm[i])]);
      }
      offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
      types.push_back(static_cast<std::uint8_t>(c.vtk_type));
    }
  }

  // 3. XML header; every DataArray points into the appended block.
  std::vector<Blob> blobs;
  std::uint64_t offset = 0;
  auto data_array = [&](std::string& xml, const char* type, const std::string& name, int components, const void* data,
                        std::uint64_t bytes) {
    xml += fmt::format("        <DataArray type=\"{}\" Name=\"{}\"", type, xml_escape(name));
    if (components > 0) xml += fmt::format(" NumberOfComponents=\"{}\"", components);
    xml += fmt::format(" format=\"appended\" offset=\"{}\"/>\n", offset);
    blobs.push_back({data, bytes});
    offset += sizeof(std::uint64_t) + bytes;
  };
  auto field_arrays = [&](std::string& xml, const std::vector<VtuField>& fields) {
    for (const auto& f : fields) {
      data_array(xml, "Float64", f.name, f.components, f.values.data(), f.values.size() * sizeof(double));
    }
  };

  std::string xml;
  xml += "<?xml version=\"1.0\"?>\n";
  xml += fmt::format(
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"{}\" "
      "header_type=\"UInt64\">\n",
      std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian");
  xml += "  <UnstructuredGrid>\n";
  if (grid.time) {
    xml += "    <FieldData>\n";
    xml += fmt::format(
        "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" "
        "format=\"ascii\">{}</DataArray>\n",
        double_text(*grid.time));
    xml += "    </FieldData>\n";
  }
  xml += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", n_points, n_cells);
  xml += "      <PointData>\n";
  field_arrays(xml, grid.point_fields);
  xml += "      </PointData>\n";
  xml += "      <CellData>\n";
  field_arrays(xml, grid.cell_fields);
  xml += "      </CellData>\n";
  xml += "      <Points>\n";
  data_array(xml, "Float64", "Points", 3, grid.points.data(), grid.points.size() * sizeof(double));
  xml += "      </Points>\n";
  xml += "      <Cells>\n";
  data_array(xml, "Int64", "connectivity", 0, connectivity.data(), connectivity.size() * sizeof(std::int64_t));
  data_array(xml, "Int64", "offsets", 0, offsets.data(), offsets.size() * sizeof(std::int64_t));
  data_array(xml, "UInt8", "types", 0, types.data(), types.size());
  xml += "      </Cells>\n";
  xml += "    </Piece>\n";
  xml += "  </UnstructuredGrid>\n";
  xml += "  <AppendedData encoding=\"raw\">\n   _";

  // 4. Header, raw arrays (each preceded by its byte count), footer; via <path>.tmp.
  write_file_atomically(path, [&](std::ostream& os) {
    os.write(xml.data(), static_cast<std::streamsize>(xml.size()));
    for (const auto& b : blobs) {
      os.write(reinterpret_cast<const char*>(&b.bytes), sizeof b.bytes);
      if (b.bytes > 0) {
        os.write(static_cast<const char*>(b.data), static_cast<std::streamsize>(b.bytes));
      }
    }
    const std::string_view footer = "\n  </AppendedData>\n</VTKFile>\n";
    os.write(footer.data(), static_cast<std::streamsize>(footer.size()));
  });
}

void write_pvtu(const std::filesystem::path& path, const std::vector<std::string>& pieces,
                const std::vector<PvtuArray>& point_arrays, const std::vector<PvtuArray>& cell_arrays) {
  if (pieces.empty()) throw Error(fmt::format("{}: a .pvtu needs at least one piece", path.string()));
  const auto arrays = [](const std::vector<PvtuArray>& list) {
    std::string xml;
    for (const PvtuArray& a : list)
      xml += fmt::format("      <PDataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\"/>\n",
                         xml_escape(a.name), a.components);
    return xml;
  };
  std::string xml = "<?xml version=\"1.0\"?>\n";
  xml += fmt::format("<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"{}\" header_type=\"UInt64\">\n",
                     std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian");
  xml += "  <PUnstructuredGrid GhostLevel=\"0\">\n";
  xml += "    <PPointData>\n" + arrays(point_arrays) + "    </PPointData>\n";
  xml += "    <PCellData>\n" + arrays(cell_arrays) + "    </PCellData>\n";
  xml +=
      "    <PPoints>\n      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n    </PPoints>\n";
  for (const std::string& piece : pieces) xml += fmt::format("    <Piece Source=\"{}\"/>\n", xml_escape(piece));
  xml += "  </PUnstructuredGrid>\n</VTKFile>\n";
  write_file_atomically(path, xml);
}

}  // namespace shellflow::io
