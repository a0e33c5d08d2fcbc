#pragma once
// The shell's shape functions at its load points, evaluated once: per load point the
// element's nodes, phi_j, dphi_j/dxi_a and the in-plane quadrature weight w_q (the
// LoadPoint's reference area weight divided by |X_1 x X_2|). Piston theory and the force
// balance of the partitioned driver read it.
#include <Eigen/Core>
#include <vector>

#include "shellflow/shell/shell_model.h"

namespace shellflow::coupling {

struct LoadPointBasis {
  explicit LoadPointBasis(const shell::ShellModel& model);

  int n = 0;                         ///< nodes per element
  std::vector<Index> nodes;          ///< n per load point
  std::vector<double> phi;           ///< n per load point
  std::vector<double> dphi;          ///< 2 n per load point: (d/dxi1, d/dxi2) of each node's function
  std::vector<double> plane_weight;  ///< per load point

  std::size_t size() const { return plane_weight.size(); }
  /// Tangents x_1, x_2 at load point k of the configuration X + u (u: 7 per node).
  void tangents(const shell::ShellModel& model, std::size_t k, const Eigen::VectorXd* u, Vec3& x1, Vec3& x2) const;
};

}  // namespace shellflow::coupling
