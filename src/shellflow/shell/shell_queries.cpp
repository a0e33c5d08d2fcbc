#include "shellflow/shell/shell_queries.h"

#include <array>
#include <cmath>
#include <limits>

#include "shellflow/core/error.h"
#include "shellflow/fem/reference_element.h"
#include "shellflow/shell/shell_model_loops.h"

namespace shellflow::shell {

namespace {

/// Calls f(N, dN, conn) with the shape functions (values, row-major gradients) at p.
template <class F>
void with_shape_functions(const ShellModel& model, const ShellPoint& p, F&& f) {
  const mesh::Mesh& m = model.mesh();
  if (p.element < 0 || p.element >= m.num_cells())
    throw InputError(fmt::format("shell query: element {} does not exist (mesh '{}' has {} elements)", p.element,
                                 m.name, m.num_cells()));
  fem::visit_element_type(static_cast<int>(m.cells.type), [&](auto element) {
    using E = decltype(element);
    if constexpr (E::dim == 2) {
      double N[E::num_nodes], dN[2 * E::num_nodes];
      E::eval(p.xi.data(), N);
      E::eval_gradients(p.xi.data(), dN);
      f(E::num_nodes, N, dN, m.cells.element(p.element));
    }
  });
}

}  // namespace

Vec3 interpolate_nodal(const ShellModel& model, const ShellPoint& p, const Eigen::VectorXd& nodal, int component) {
  Vec3 value = Vec3::Zero();
  with_shape_functions(model, p, [&](int n, const double* N, const double*, std::span<const Index> conn) {
    for (int j = 0; j < n; ++j)
      value += N[j] * nodal.segment<3>(dofs_per_node * conn[static_cast<std::size_t>(j)] + component);
  });
  return value;
}

Vec3 mid_surface_position(const ShellModel& model, const ShellPoint& p, const Eigen::VectorXd& u) {
  Vec3 x = Vec3::Zero();
  with_shape_functions(model, p, [&](int n, const double* N, const double*, std::span<const Index> conn) {
    for (int j = 0; j < n; ++j) {
      const Index node = conn[static_cast<std::size_t>(j)];
      x += N[j] * (model.mesh().nodes[static_cast<std::size_t>(node)] + node_position_increment(u, node));
    }
  });
  return x;
}

Vec3 mid_surface_normal(const ShellModel& model, const ShellPoint& p, const Eigen::VectorXd& u) {
  Vec3 t1 = Vec3::Zero(), t2 = Vec3::Zero();
  with_shape_functions(model, p, [&](int n, const double*, const double* dN, std::span<const Index> conn) {
    for (int j = 0; j < n; ++j) {
      const Index node = conn[static_cast<std::size_t>(j)];
      const Vec3 x = model.mesh().nodes[static_cast<std::size_t>(node)] + node_position_increment(u, node);
      t1 += dN[2 * j] * x;
      t2 += dN[2 * j + 1] * x;
    }
  });
  return t1.cross(t2).normalized();
}

namespace {

std::vector<Vec3> current_positions(const ShellModel& model, const Eigen::VectorXd& u) {
  if (u.size() != model.num_dofs())
    throw_input_error("shell locator: state has {} entries, the model '{}' has {} dofs", u.size(), model.mesh().name,
                      model.num_dofs());
  std::vector<Vec3> x = model.mesh().nodes;
  for (Index n = 0; n < model.num_nodes(); ++n) x[static_cast<std::size_t>(n)] += node_position_increment(u, n);
  return x;
}

/// The mid-surface map of one element and its first and second derivatives in ξ.
template <class Tri>
struct SurfacePatch {
  static constexpr int N = Tri::num_nodes;
  std::array<Vec3, N> x;
  Vec3 pos, d[2], dd[3];  // dd: ξ1ξ1, ξ1ξ2, ξ2ξ2

  void evaluate(const Vec2& xi) {
    double phi[N], dphi[2 * N], d2phi[4 * N];
    Tri::eval(xi.data(), phi);
    Tri::eval_gradients(xi.data(), dphi);
    Tri::eval_hessians(xi.data(), d2phi);
    pos = d[0] = d[1] = dd[0] = dd[1] = dd[2] = Vec3::Zero();
    for (int j = 0; j < N; ++j) {
      pos += phi[j] * x[static_cast<std::size_t>(j)];
      d[0] += dphi[2 * j] * x[static_cast<std::size_t>(j)];
      d[1] += dphi[2 * j + 1] * x[static_cast<std::size_t>(j)];
      dd[0] += d2phi[4 * j] * x[static_cast<std::size_t>(j)];
      dd[1] += d2phi[4 * j + 1] * x[static_cast<std::size_t>(j)];
      dd[2] += d2phi[4 * j + 3] * x[static_cast<std::size_t>(j)];
    }
  }
};

bool inside_triangle(const Vec2& xi, double tol) { return xi(0) >= -tol && xi(1) >= -tol && xi.sum() <= 1.0 + tol; }

/// Largest tau in [0, 1] with xi + tau step inside the reference triangle.
double step_to_boundary(const Vec2& xi, const Vec2& step) {
  double tau = 1.0;
  if (step(0) < 0.0) tau = std::min(tau, -xi(0) / step(0));
  if (step(1) < 0.0) tau = std::min(tau, -xi(1) / step(1));
  if (step.sum() > 0.0) tau = std::min(tau, (1.0 - xi.sum()) / step.sum());
  return std::max(tau, 0.0);
}

/// Newton on ξ for min |x̂(ξ) − p|² over the reference triangle. Uses the full Hessian
/// JᵀJ + r·x̂_αβ when it is positive definite (quadratic convergence also at an offset),
/// else Gauss–Newton; steps are cut at the triangle's boundary, and when the minimiser
/// lies outside, the three edges are searched (1-D Newton, clamped to the edge).
template <class Tri>
Vec2 project_on_patch(SurfacePatch<Tri>& patch, const Vec3& p, Vec2 xi) {
  constexpr int max_iterations = 100;
  constexpr double tol = 1e-15;
  int blocked = 0;
  for (int it = 0; it < max_iterations; ++it) {
    patch.evaluate(xi);
    const Vec3 r = patch.pos - p;
    const Vec2 g(patch.d[0].dot(r), patch.d[1].dot(r));
    Eigen::Matrix2d H;
    H << patch.d[0].dot(patch.d[0]), patch.d[0].dot(patch.d[1]), patch.d[0].dot(patch.d[1]), patch.d[1].dot(patch.d[1]);
    Eigen::Matrix2d Hc = H;
    Hc(0, 0) += r.dot(patch.dd[0]);
    Hc(0, 1) += r.dot(patch.dd[1]);
    Hc(1, 0) += r.dot(patch.dd[1]);
    Hc(1, 1) += r.dot(patch.dd[2]);
    if (Hc(0, 0) > 0.0 && Hc.determinant() > 0.0) H = Hc;
    const Vec2 step = -H.ldlt().solve(g);
    if (!step.allFinite()) break;
    const double tau = step_to_boundary(xi, step);
    xi += tau * step;
    if (tau < 1.0) {
      if (++blocked >= 2 && tau * step.norm() < 1e-12) break;  // held at the boundary: search the edges
      continue;
    }
    blocked = 0;
    if (step.norm() < tol) return xi;
  }
  if (inside_triangle(xi, 0.0) && xi(0) > 0.0 && xi(1) > 0.0 && xi.sum() < 1.0 && blocked == 0) return xi;
  // Edges ξ(s) = start + s dir, s in [0, 1].
  const std::array<std::pair<Vec2, Vec2>, 3> edges{
      std::pair{Vec2(0, 0), Vec2(1, 0)}, std::pair{Vec2(1, 0), Vec2(-1, 1)}, std::pair{Vec2(0, 1), Vec2(0, -1)}};
  Vec2 best = xi;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (const auto& [start, dir] : edges) {
    double s = std::clamp((xi - start).dot(dir) / dir.squaredNorm(), 0.0, 1.0);
    for (int it = 0; it < max_iterations; ++it) {
      patch.evaluate(start + s * dir);
      const Vec3 r = patch.pos - p;
      const Vec3 t = dir(0) * patch.d[0] + dir(1) * patch.d[1];
      const Vec3 tt =
          dir(0) * dir(0) * patch.dd[0] + 2.0 * dir(0) * dir(1) * patch.dd[1] + dir(1) * dir(1) * patch.dd[2];
      double h = t.dot(t) + r.dot(tt);
      if (!(h > 0.0)) h = t.dot(t);
      const double next = std::clamp(s - t.dot(r) / h, 0.0, 1.0);
      const double ds = next - s;
      s = next;
      if (std::abs(ds) < tol) break;
    }
    patch.evaluate(start + s * dir);
    const double d2 = (patch.pos - p).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = start + s * dir;
    }
  }
  return best;
}

}  // namespace

ShellLocator::ShellLocator(const ShellModel& model) : ShellLocator(model, Eigen::VectorXd::Zero(model.num_dofs())) {}

ShellLocator::ShellLocator(const ShellModel& model, const Eigen::VectorXd& u)
    : model_(model),
      positions_(current_positions(model, u)),
      tree_(mesh::element_boxes(positions_, model.mesh().cells, 0.05)) {}

ClosestPoint ShellLocator::closest_on_element(Index element, const Vec3& p) const {
  const mesh::Mesh& m = model_.mesh();
  if (element < 0 || element >= m.num_cells())
    throw_input_error("shell locator: element {} does not exist (mesh '{}' has {} elements)", element, m.name,
                      m.num_cells());
  if (!p.allFinite()) throw_input_error("shell locator: query point ({}, {}, {}) is not finite", p.x(), p.y(), p.z());
  ClosestPoint out;
  visit_triangle(model_, [&](auto tri) {
    using Tri = decltype(tri);
    SurfacePatch<Tri> patch;
    const auto conn = m.cells.element(element);
    for (int j = 0; j < Tri::num_nodes; ++j)
      patch.x[static_cast<std::size_t>(j)] = positions_[static_cast<std::size_t>(conn[static_cast<std::size_t>(j)])];
    const Vec2 start = mesh::closest_point_on_triangle(p, patch.x[0], patch.x[1], patch.x[2]);
    const Vec2 xi = project_on_patch(patch, p, start);
    patch.evaluate(xi);
    out.point = {element, xi};
    out.position = patch.pos;
    out.distance = (p - patch.pos).norm();
    out.offset = (p - patch.pos).dot(patch.d[0].cross(patch.d[1]).normalized());
  });
  return out;
}

ClosestPoint ShellLocator::closest(const Vec3& p) const {
  if (!p.allFinite()) throw_input_error("shell locator: query point ({}, {}, {}) is not finite", p.x(), p.y(), p.z());
  const mesh::PointHit hit = tree_.nearest(p, [&](Index e) { return closest_on_element(e, p).distance; });
  return closest_on_element(hit.index, p);
}

Vec3 hermite_position(const Vec3& x0, const Vec3& v0, const Vec3& x1, const Vec3& v1, double dt, double tau) {
  const double t2 = tau * tau, t3 = t2 * tau;
  return (2 * t3 - 3 * t2 + 1) * x0 + (t3 - 2 * t2 + tau) * dt * v0 + (-2 * t3 + 3 * t2) * x1 + (t3 - t2) * dt * v1;
}

Vec3 hermite_velocity(const Vec3& x0, const Vec3& v0, const Vec3& x1, const Vec3& v1, double dt, double tau) {
  const double t2 = tau * tau;
  return ((6 * t2 - 6 * tau) * x0 + (3 * t2 - 4 * tau + 1) * dt * v0 + (-6 * t2 + 6 * tau) * x1 +
          (3 * t2 - 2 * tau) * dt * v1) /
         dt;
}

}  // namespace shellflow::shell
