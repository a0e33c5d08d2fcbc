#include "shellflow/fluid/shock_capturing.h"

#include <cmath>

namespace shellflow::fluid {

void compute_artificial_viscosity(const IdealGas& gas, double q_dif, bool smoothing, const ElementLoop& loop,
                                  const TetGeometry& g, const FluidState& u, ShockCapturingWorkspace& work,
                                  std::vector<double>& nu, const GhostExchange& exchange) {
  const Index ne = g.num_elements();
  const Index nn = u.size();
  if (q_dif <= 0.0) {
    nu.assign(std::size_t(ne), 0.0);
    return;
  }
  nu.resize(std::size_t(ne));  // every entry is written below
  const auto& tets = loop.tets;
  work.pressure.resize(std::size_t(nn));
  work.speed.resize(std::size_t(nn));
  for (auto& gr : work.gradient) gr.assign(std::size_t(nn), 0.0);
  // Nodal p and |u| + c once per node (a node is shared by ~24 tetrahedra).
  for_each_node(nn, [&](Index a) {
    const auto i = std::size_t(a);
    const double rho = u.var[0][i];
    const double p = gas.pressure(rho, u.var[1][i], u.var[2][i], u.var[3][i], u.var[4][i]);
    work.pressure[i] = p;
    work.speed[i] = std::sqrt(u.var[1][i] * u.var[1][i] + u.var[2][i] * u.var[2][i] + u.var[3][i] * u.var[3][i]) / rho +
                    gas.sound_speed(rho, p);
  });
  const auto* p = work.pressure.data();
  // 1. Lumped projection of the element pressure gradient to the nodes.
  for_each_element(loop, [&](Index e) {
    const auto ue = std::size_t(e);
    const Index* n = tets.data() + 4 * ue;
    const double* B = g.grad[ue].data();
    double gp[3] = {0.0, 0.0, 0.0};
    for (int a = 1; a < 4; ++a) {
      const double dp = p[n[a]] - p[n[0]];
      for (int j = 0; j < 3; ++j) gp[j] += dp * B[3 * a + j];
    }
    const double quarter = 0.25 * g.volume[ue];
    for (int a = 0; a < 4; ++a)
      for (int j = 0; j < 3; ++j) work.gradient[std::size_t(j)][std::size_t(n[a])] += quarter * gp[j];
  });
  for_each_node(nn, [&](Index a) {
    const double inv_mass = 1.0 / g.lumped_mass[std::size_t(a)];
    for (int j = 0; j < 3; ++j) work.gradient[std::size_t(j)][std::size_t(a)] *= inv_mass;
  });
  if (exchange) {
    double* fields[3] = {work.gradient[0].data(), work.gradient[1].data(), work.gradient[2].data()};
    exchange(fields);
  }
  // 2. Element Laplacian and the sensor-scaled viscosity; with smoothing, scattered at once
  // as V_e nu_e to the nodes (no element array in between).
  const double* gx = work.gradient[0].data();
  const double* gy = work.gradient[1].data();
  const double* gz = work.gradient[2].data();
  const double* speed = work.speed.data();
  auto raw_viscosity = [&](std::size_t ue) {
    const Index* n = tets.data() + 4 * ue;
    const double* B = g.grad[ue].data();
    // Difference form: a uniform gradient field gives exactly zero.
    const auto i0 = std::size_t(n[0]);
    double lap = 0.0;
    for (int a = 1; a < 4; ++a) {
      const auto i = std::size_t(n[a]);
      lap += B[3 * a] * (gx[i] - gx[i0]) + B[3 * a + 1] * (gy[i] - gy[i0]) + B[3 * a + 2] * (gz[i] - gz[i0]);
    }
    const double speed_sum = speed[i0] + speed[n[1]] + speed[n[2]] + speed[n[3]];
    const double p_sum = p[i0] + p[n[1]] + p[n[2]] + p[n[3]];
    const double h = g.size[ue];
    return q_dif * h * h * h * speed_sum / p_sum * std::abs(lap);
  };
  if (!smoothing) {
    for_each_element_index(ne, [&](Index e) { nu[std::size_t(e)] = raw_viscosity(std::size_t(e)); });
    return;
  }
  // 3. Nodal smoothing: nu_a = sum V_e nu_e / sum V_e (sum V_e = 4 M_a), nu_e = mean nu_a.
  work.nodal_viscosity.assign(std::size_t(nn), 0.0);
  double* nodal = work.nodal_viscosity.data();
  for_each_element(loop, [&](Index e) {
    const auto ue = std::size_t(e);
    const double vn = g.volume[ue] * raw_viscosity(ue);
    const Index* n = tets.data() + 4 * ue;
    for (int a = 0; a < 4; ++a) nodal[n[a]] += vn;
  });
  for_each_node(nn, [&](Index a) { nodal[a] /= 4.0 * g.lumped_mass[std::size_t(a)]; });
  if (exchange) {
    double* fields[1] = {nodal};
    exchange(fields);
  }
  for_each_element_index(ne, [&](Index e) {
    const Index* n = tets.data() + 4 * std::size_t(e);
    nu[std::size_t(e)] = 0.25 * (nodal[n[0]] + nodal[n[1]] + nodal[n[2]] + nodal[n[3]]);
  });
}

}  // namespace shellflow::fluid
