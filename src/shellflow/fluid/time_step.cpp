#include "shellflow/fluid/time_step.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "shellflow/fluid/element_loop.h"

namespace shellflow::fluid {

double min_element_time_step(const IdealGas& gas, std::span<const Index> tets, const TetGeometry& g,
                             const FluidState& u, std::span<const Vec3> w, std::span<const double> nu,
                             std::vector<std::array<double, 4>>& nodal, std::vector<double>* element_dt) {
  // Nodal relative velocity and sound speed once per node (6x fewer roots and divisions
  // than per element corner).
  const Index nn = u.size();
  nodal.resize(std::size_t(nn));
  for_each_node(nn, [&](Index a) {
    const auto i = std::size_t(a);
    const double rho = u.var[0][i];
    const double inv_rho = 1.0 / rho;
    const double p = gas.pressure(rho, u.var[1][i], u.var[2][i], u.var[3][i], u.var[4][i]);
    nodal[i] = {u.var[1][i] * inv_rho - w[i].x(), u.var[2][i] * inv_rho - w[i].y(), u.var[3][i] * inv_rho - w[i].z(),
                std::sqrt(gas.gamma * p * inv_rho)};
  });
  const Index ne = g.num_elements();
  if (element_dt) element_dt->resize(std::size_t(ne));
  return reduce_items(
      ne, parallel::kElementGrain, parallel_threshold, std::numeric_limits<double>::infinity(),
      [&](Index e) {
        const auto ue = std::size_t(e);
        double sum[4] = {0.0, 0.0, 0.0, 0.0};
        for (int a = 0; a < 4; ++a) {
          const auto& q = nodal[std::size_t(tets[4 * ue + std::size_t(a)])];
          for (int j = 0; j < 4; ++j) sum[j] += q[std::size_t(j)];
        }
        const double h = g.size[ue];
        const double speed = 0.25 * (std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]) + sum[3]);
        double dt = h / speed;
        if (!nu.empty() && nu[ue] > 0.0) dt = std::min(dt, h * h / (2.0 * nu[ue]));
        if (element_dt) (*element_dt)[ue] = dt;
        return dt;
      },
      [](double p, double q) { return std::min(p, q); });
}

}  // namespace shellflow::fluid
