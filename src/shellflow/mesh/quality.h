#pragma once
// Element quality: signed volume and mean-ratio quality of tetrahedra (computed from the
// four vertices, so it applies to any order), and the shape quality of triangles.
#include <vector>

#include "shellflow/core/types.h"
#include "shellflow/mesh/mesh.h"

namespace shellflow::mesh {

/// Signed volume of the tetrahedron (a, b, c, d); positive for Gmsh's orientation.
double tet_signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Mean-ratio quality q = 12 (3|V|)^(2/3) / sum of squared edge lengths: 1 for the
/// regular tetrahedron, -> 0 when degenerate, and negative (-q) when inverted.
double tet_mean_ratio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Triangle shape quality 4 sqrt(3) area / sum of squared edge lengths (1: equilateral).
double triangle_quality(const Vec3& a, const Vec3& b, const Vec3& c);

/// Quality of every cell of a mesh (tetrahedra: mean ratio, signed; triangles: shape
/// quality, >= 0), from the cell's vertices. `positions` overrides the mesh's nodes
/// (e.g. a deformed configuration) when not empty.
std::vector<double> cell_qualities(const Mesh& mesh, std::span<const Vec3> positions = {});

struct QualitySummary {
  double min = 0.0;  ///< smallest quality (negative if any cell is inverted)
  double mean = 0.0;
  Index worst_cell = -1;    ///< index of the cell with the smallest quality
  Index inverted = 0;       ///< number of cells with non-positive volume (tetrahedra)
  double min_volume = 0.0;  ///< smallest signed volume (tetrahedra) or area (triangles)
  double min_ratio = 1.0;   ///< smallest ratio of a cell's quality to its `reference` quality
};
/// The quality of every cell summarised (at `positions` when not empty); with `reference`
/// (one quality per cell, e.g. cell_qualities of the initial mesh) also the smallest ratio
/// to it: the one scan behind `shellflow mesh`, the runs' quality histories and the
/// inverted-element checks of a moving mesh.
QualitySummary summarize_quality(const Mesh& mesh, std::span<const Vec3> positions = {},
                                 std::span<const double> reference = {});

/// The centroid of a cell's vertices (at `positions` when not empty): where a message puts
/// a bad cell.
Vec3 vertex_centroid(const Mesh& mesh, Index cell, std::span<const Vec3> positions = {});

}  // namespace shellflow::mesh
