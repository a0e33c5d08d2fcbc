#include "shellflow/mesh/quality.h"

#include <cmath>
#include <limits>

namespace shellflow::mesh {

double tet_signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).cross(c - a).dot(d - a) / 6.0;
}

double tet_mean_ratio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double volume = tet_signed_volume(a, b, c, d);
  const double edges = (b - a).squaredNorm() + (c - a).squaredNorm() + (d - a).squaredNorm() + (c - b).squaredNorm() +
                       (d - b).squaredNorm() + (d - c).squaredNorm();
  if (edges == 0.0) return 0.0;
  const double q = 12.0 * std::cbrt(9.0 * volume * volume) / edges;  // (3|V|)^(2/3)
  return volume < 0.0 ? -q : q;
}

double triangle_quality(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double area = 0.5 * (b - a).cross(c - a).norm();
  const double edges = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  return edges == 0.0 ? 0.0 : 4.0 * std::sqrt(3.0) * area / edges;
}

namespace {

template <class F>
void for_each_cell_vertices(const Mesh& mesh, std::span<const Vec3> x, F&& f) {
  const auto& info = element_info(mesh.cells.type);
  for (Index e = 0; e < mesh.num_cells(); ++e) {
    const auto nodes = mesh.cells.element(e);
    if (info.dim == 3) {
      f(e, x[nodes[0]], x[nodes[1]], x[nodes[2]], &x[nodes[3]]);
    } else {
      f(e, x[nodes[0]], x[nodes[1]], x[nodes[2]], nullptr);
    }
  }
}

std::span<const Vec3> positions_or_nodes(const Mesh& mesh, std::span<const Vec3> positions) {
  return positions.empty() ? std::span<const Vec3>(mesh.nodes) : positions;
}

}  // namespace

std::vector<double> cell_qualities(const Mesh& mesh, std::span<const Vec3> positions) {
  std::vector<double> q(static_cast<std::size_t>(mesh.num_cells()));
  for_each_cell_vertices(mesh, positions_or_nodes(mesh, positions),
                         [&](Index e, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3* d) {
                           q[static_cast<std::size_t>(e)] = d ? tet_mean_ratio(a, b, c, *d) : triangle_quality(a, b, c);
                         });
  return q;
}

QualitySummary summarize_quality(const Mesh& mesh, std::span<const Vec3> positions, std::span<const double> reference) {
  QualitySummary s;
  if (!reference.empty()) s.min_ratio = std::numeric_limits<double>::infinity();
  s.min = std::numeric_limits<double>::infinity();
  s.min_volume = std::numeric_limits<double>::infinity();
  double sum = 0.0;
  for_each_cell_vertices(mesh, positions_or_nodes(mesh, positions),
                         [&](Index e, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3* d) {
                           const double q = d ? tet_mean_ratio(a, b, c, *d) : triangle_quality(a, b, c);
                           const double v = d ? tet_signed_volume(a, b, c, *d) : 0.5 * (b - a).cross(c - a).norm();
                           sum += q;
                           if (!reference.empty())
                             s.min_ratio = std::min(s.min_ratio, q / reference[static_cast<std::size_t>(e)]);
                           if (q < s.min || (std::isnan(q) && !std::isnan(s.min))) {  // NaN is the worst
                             s.min = q;
                             s.worst_cell = e;
                           }
                           if (v < s.min_volume) s.min_volume = v;
                           if (d && !(v > 0.0)) ++s.inverted;  // NaN counts as inverted
                         });
  if (mesh.num_cells() > 0) s.mean = sum / mesh.num_cells();
  return s;
}

Vec3 vertex_centroid(const Mesh& mesh, Index cell, std::span<const Vec3> positions) {
  const auto x = positions_or_nodes(mesh, positions);
  const auto v = mesh.cells.element(cell);
  const int corners = mesh.dim() == 3 ? 4 : 3;
  Vec3 c = Vec3::Zero();
  for (int k = 0; k < corners; ++k) c += x[static_cast<std::size_t>(v[static_cast<std::size_t>(k)])];
  return c / corners;
}

}  // namespace shellflow::mesh
