#include "shellflow/shell/shell_queries.h"

#include "shellflow/core/error.h"
#include "shellflow/fem/reference_element.h"

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
