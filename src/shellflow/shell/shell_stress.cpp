#include "shellflow/shell/shell_stress.h"

#include <cmath>

#include "shellflow/core/error.h"
#include "shellflow/fem/reference_element.h"
#include "shellflow/shell/shell_model_loops.h"

namespace shellflow::shell {

namespace {

/// Stress point of element e of type Tri at (xi, xi3). The current map comes from the
/// kernel (detail::PlanePoint::delta_A, increment form); A0 repeats the formula of
/// ShellElementGeometry's constructor at an arbitrary point (shell.md §2.4).
template <class Tri>
StressPoint evaluate(const ShellModel& model, const Eigen::VectorXd& u, Index e, const double* xi, double xi3) {
  constexpr int N = Tri::num_nodes;
  const mesh::Mesh& m = model.mesh();
  const auto conn = m.cells.element(e);
  ShellElementGeometry<Tri> geo;
  Eigen::Matrix<double, dofs_per_node * N, 1> ue;
  for (int j = 0; j < N; ++j) {
    const auto node = static_cast<std::size_t>(conn[static_cast<std::size_t>(j)]);
    geo.X.col(j) = m.nodes[node];
    geo.V.col(j) = model.directors()[node];
    ue.template segment<dofs_per_node>(dofs_per_node * j) =
        u.segment<dofs_per_node>(dofs_per_node * static_cast<Eigen::Index>(node));
  }
  geo.h.setConstant(model.section().thickness);
  Eigen::Matrix<double, N, 1> phi;
  Eigen::Matrix<double, N, 2, Eigen::RowMajor> dN;
  Tri::eval(xi, phi.data());
  Tri::eval_gradients(xi, dN.data());
  const Eigen::Matrix<double, N, 2> dphi = dN;

  Mat3 A0;
  const Vec3 V_hat = geo.V * phi;
  const double h_hat = geo.h.dot(phi);
  for (int al = 0; al < 2; ++al)
    A0.col(al) = geo.X * dphi.col(al) + 0.5 * xi3 * (geo.h.dot(dphi.col(al)) * V_hat + h_hat * (geo.V * dphi.col(al)));
  A0.col(2) = 0.5 * h_hat * V_hat;

  detail::PlanePoint<N> p;
  p.interpolate(geo, phi, dphi, ue);
  StressPoint s;
  const Mat3 H = p.delta_A(xi3) * A0.inverse();
  s.F = Mat3::Identity() + H;
  const double J = s.F.determinant();
  if (!(J > 0.0))
    throw SolverError(
        fmt::format("shell stress: det F = {:.3g} <= 0 in element {} of mesh '{}' (inverted state)", J, e, m.name));
  const SvkMaterial& material = model.section().material;
  s.E = detail::green_lagrange(H);
  s.S = detail::svk_stress(s.E, material.lame_lambda(), material.lame_mu());
  s.sigma = s.F * s.S * s.F.transpose() / J;
  return s;
}

}  // namespace

StressPoint stress_at(const ShellModel& model, const Eigen::VectorXd& u, const ShellPoint& p, double xi3) {
  const mesh::Mesh& m = model.mesh();
  if (p.element < 0 || p.element >= m.num_cells())
    throw_input_error("shell stress: element {} does not exist (mesh '{}' has {} elements)", p.element, m.name,
                      m.num_cells());
  if (!(xi3 >= -1.0 && xi3 <= 1.0))
    throw_input_error("shell stress: thickness coordinate xi3 must be in [-1, 1] (got {})", xi3);
  StressPoint s;
  visit_triangle(model, [&](auto element) { s = evaluate<decltype(element)>(model, u, p.element, p.xi.data(), xi3); });
  return s;
}

const Mat3& select(const StressPoint& s, StressMeasure measure) {
  switch (measure) {
    case StressMeasure::green_lagrange_strain:
      return s.E;
    case StressMeasure::second_piola_kirchhoff:
      return s.S;
    case StressMeasure::cauchy:
      break;
  }
  return s.sigma;
}

double von_mises(const Mat3& T) {
  const Mat3 dev = T - T.trace() / 3.0 * Mat3::Identity();
  return std::sqrt(1.5 * dev.squaredNorm());
}

NodalStresses nodal_stresses(const ShellModel& model, const Eigen::VectorXd& u, StressMeasure measure,
                             SurfaceSide side) {
  const mesh::Mesh& m = model.mesh();
  const auto n = static_cast<std::size_t>(m.num_nodes());
  NodalStresses out;
  out.tensor.assign(n, Mat3::Zero());
  out.von_mises.assign(n, 0.0);
  std::vector<int> count(n, 0);
  const double xi3 = static_cast<double>(static_cast<int>(side));
  visit_triangle(model, [&](auto element) {
    using E = decltype(element);
    for (Index e = 0; e < m.num_cells(); ++e) {
      const auto conn = m.cells.element(e);
      for (int a = 0; a < E::num_nodes; ++a) {
        const StressPoint s = evaluate<E>(model, u, e, E::node_points[static_cast<std::size_t>(a)].data(), xi3);
        const auto node = static_cast<std::size_t>(conn[static_cast<std::size_t>(a)]);
        out.tensor[node] += select(s, measure);
        ++count[node];
      }
    }
  });
  for (std::size_t k = 0; k < n; ++k) {
    if (count[k] > 0) out.tensor[k] /= count[k];
    // Symmetric by construction up to round-off; make it exact for output.
    out.tensor[k] = 0.5 * (out.tensor[k] + out.tensor[k].transpose()).eval();
    out.von_mises[k] = von_mises(out.tensor[k]);
  }
  return out;
}

}  // namespace shellflow::shell
