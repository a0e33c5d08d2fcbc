#pragma once
// Writing shellflow meshes (with fields) as `.vtu`.
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

#include "shellflow/io/vtu_writer.h"
#include "shellflow/mesh/mesh.h"

namespace shellflow::io {

/// Writes the mesh's cells with the given fields, plus the cell field `quality` (mean
/// ratio for tetrahedra, shape quality for triangles). `positions` replaces the mesh's
/// node coordinates when not empty (a deformed configuration).
void write_mesh_vtu(const std::filesystem::path& path, const mesh::Mesh& m, std::vector<VtuField> point_fields = {},
                    std::optional<double> time = {}, std::span<const Vec3> positions = {});

}  // namespace shellflow::io
