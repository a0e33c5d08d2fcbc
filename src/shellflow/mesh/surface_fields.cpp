#include "shellflow/mesh/surface_fields.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "shellflow/core/error.h"
#include "shellflow/fem/quadrature.h"
#include "shellflow/fem/reference_element.h"

namespace shellflow::mesh {
namespace {

/// ∫ (∇_s f · d)² and ∫ f² over one element type's cells.
template <class Tri>
void integrate(const Mesh& surface, std::span<const double> f, const Vec3& d, double& gradient, double& value) {
  const fem::QuadratureRule& rule = fem::triangle_rule(2 * Tri::order);
  for (Index e = 0; e < surface.num_cells(); ++e) {
    const auto nodes = surface.cells.element(e);
    for (int q = 0; q < rule.size(); ++q) {
      const auto N = Tri::values(typename Tri::Coords(rule.point(q).data()));
      const auto dN = Tri::gradients(typename Tri::Coords(rule.point(q).data()));
      Vec3 a1 = Vec3::Zero(), a2 = Vec3::Zero();
      double fq = 0.0, f1 = 0.0, f2 = 0.0;
      for (int j = 0; j < Tri::num_nodes; ++j) {
        const auto n = static_cast<std::size_t>(nodes[static_cast<std::size_t>(j)]);
        a1 += dN(j, 0) * surface.nodes[n];
        a2 += dN(j, 1) * surface.nodes[n];
        fq += N(j) * f[n];
        f1 += dN(j, 0) * f[n];
        f2 += dN(j, 1) * f[n];
      }
      // Surface gradient f_,α a^α with the contravariant basis a^α = g^{αβ} a_β.
      const double g11 = a1.dot(a1), g12 = a1.dot(a2), g22 = a2.dot(a2);
      const double det = g11 * g22 - g12 * g12;
      const Vec3 gradient_s = ((g22 * f1 - g12 * f2) * a1 + (g11 * f2 - g12 * f1) * a2) / det;
      const double dA = rule.weights[static_cast<std::size_t>(q)] * std::sqrt(det);
      gradient += std::pow(gradient_s.dot(d), 2) * dA;
      value += fq * fq * dA;
    }
  }
}

}  // namespace

double directional_wavenumber(const Mesh& surface, std::span<const double> f, const Vec3& direction) {
  if (surface.dim() != 2)
    throw InputError(fmt::format("{}: a directional wavenumber needs a triangle mesh", surface.source));
  if (static_cast<Index>(f.size()) != surface.num_nodes())
    throw InputError(fmt::format("{}: {} nodal values for {} nodes", surface.source, f.size(), surface.num_nodes()));
  const Vec3 d = direction.normalized();
  double gradient = 0.0, value = 0.0;
  fem::visit_element_type(static_cast<int>(surface.cells.type), [&]<class E>(E) {
    if constexpr (E::dim == 2) integrate<E>(surface, f, d, gradient, value);
  });
  if (!(value > 0.0)) throw InputError(fmt::format("{}: the field is zero on the whole surface", surface.source));
  return std::sqrt(gradient / value);
}

double mean_extent(const Mesh& mesh, const ElementBlock& facets, const Vec3& direction) {
  if (facets.size() == 0) return 0.0;
  const Vec3 d = direction.normalized();
  const int corners = element_info(static_cast<int>(facets.type)).num_vertices;
  double sum = 0.0;
  for (Index e = 0; e < facets.size(); ++e) {
    const auto nodes = facets.element(e);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int a = 0; a < corners; ++a) {
      const double s = mesh.nodes[static_cast<std::size_t>(nodes[static_cast<std::size_t>(a)])].dot(d);
      lo = std::min(lo, s);
      hi = std::max(hi, s);
    }
    sum += hi - lo;
  }
  return sum / static_cast<double>(facets.size());
}

}  // namespace shellflow::mesh
