#include "shellflow/coupling/load_point_basis.h"

#include "shellflow/fem/reference_element.h"

namespace shellflow::coupling {

LoadPointBasis::LoadPointBasis(const shell::ShellModel& model) {
  const mesh::Mesh& m = model.mesh();
  const fem::ReferenceElement& ref = fem::reference_element(static_cast<int>(m.cells.type));
  n = ref.num_nodes;
  const auto nn = static_cast<std::size_t>(n);
  const auto& points = model.load_points();
  nodes.resize(nn * points.size());
  phi.resize(nn * points.size());
  dphi.resize(2 * nn * points.size());
  plane_weight.resize(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    const double xi[2] = {points[k].point.xi.x(), points[k].point.xi.y()};
    ref.eval(xi, phi.data() + nn * k);
    ref.eval_gradients(xi, dphi.data() + 2 * nn * k);
    const auto conn = m.cells.element(points[k].point.element);
    for (std::size_t a = 0; a < nn; ++a) nodes[nn * k + a] = conn[a];
    Vec3 X1, X2;
    tangents(model, k, nullptr, X1, X2);
    plane_weight[k] = points[k].weight / X1.cross(X2).norm();
  }
}

void LoadPointBasis::tangents(const shell::ShellModel& model, std::size_t k, const Eigen::VectorXd* u, Vec3& x1,
                              Vec3& x2) const {
  const auto nn = static_cast<std::size_t>(n);
  x1.setZero();
  x2.setZero();
  for (std::size_t a = 0; a < nn; ++a) {
    const auto j = static_cast<std::size_t>(nodes[nn * k + a]);
    Vec3 x = model.mesh().nodes[j];
    if (u) x += u->segment<3>(shell::dofs_per_node * Eigen::Index(j));
    x1 += dphi[2 * nn * k + 2 * a] * x;
    x2 += dphi[2 * nn * k + 2 * a + 1] * x;
  }
}

}  // namespace shellflow::coupling
