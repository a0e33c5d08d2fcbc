#include "shellflow/io/mesh_output.h"

#include "shellflow/mesh/quality.h"

namespace shellflow::io {

void write_mesh_vtu(const std::filesystem::path& path, const mesh::Mesh& m, std::vector<VtuField> point_fields,
                    std::optional<double> time, std::span<const Vec3> positions) {
  const std::span<const Vec3> x = positions.empty() ? std::span<const Vec3>(m.nodes) : positions;
  const std::vector<double> quality = mesh::cell_qualities(m, x);
  VtuGrid grid;
  grid.points = flat(x);
  grid.cells.push_back({static_cast<int>(m.cells.type), m.cells.connectivity});
  grid.point_fields = std::move(point_fields);
  grid.cell_fields.push_back({"quality", 1, quality});
  grid.time = time;
  write_vtu(path, grid);
}

}  // namespace shellflow::io
