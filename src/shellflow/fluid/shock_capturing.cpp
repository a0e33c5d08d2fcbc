#include "shellflow/fluid/shock_capturing.h"

#include <cmath>

namespace shellflow::fluid {

void compute_artificial_viscosity(const IdealGas& gas, double q_dif, bool smoothing,
                                  const ElementLoop& loop, const TetGeometry& g,
                                  const FluidState& u, ShockCapturingWorkspace& work,
                                  std::vector<double>& nu) {
  const Index ne = g.num_elements();
  const Index nn = u.size();
  nu.assign(std::size_t(ne), 0.0);
  if (q_dif <= 0.0) return;
  const auto& tets = loop.tets;
  work.pressure.resize(std::size_t(nn));
  for (auto& gr : work.gradient) gr.assign(std::size_t(nn), 0.0);
#pragma omp parallel for schedule(static) if (nn > parallel_threshold)
  for (Index a = 0; a < nn; ++a) {
    const auto i = std::size_t(a);
    work.pressure[i] = gas.pressure(u.var[0][i], u.var[1][i], u.var[2][i], u.var[3][i],
                                    u.var[4][i]);
  }
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
#pragma omp parallel for schedule(static) if (nn > parallel_threshold)
  for (Index a = 0; a < nn; ++a)
    for (int j = 0; j < 3; ++j) work.gradient[std::size_t(j)][std::size_t(a)] /= g.lumped_mass[std::size_t(a)];
  // 2. Element Laplacian and the sensor-scaled viscosity.
  auto& raw = smoothing ? work.raw_viscosity : nu;
  raw.assign(std::size_t(ne), 0.0);
#pragma omp parallel for schedule(static) if (ne > parallel_threshold)
  for (Index e = 0; e < ne; ++e) {
    const auto ue = std::size_t(e);
    const Index* n = tets.data() + 4 * ue;
    const double* B = g.grad[ue].data();
    double lap = 0.0;
    double speed = 0.0, sound = 0.0, pm = 0.0;
    for (int a = 0; a < 4; ++a) {
      const auto i = std::size_t(n[a]);
      // Difference form: a uniform gradient field gives exactly zero.
      if (a > 0)
        for (int j = 0; j < 3; ++j)
          lap += B[3 * a + j] *
                 (work.gradient[std::size_t(j)][i] - work.gradient[std::size_t(j)][std::size_t(n[0])]);
      const double rho = u.var[0][i];
      speed += std::sqrt(u.var[1][i] * u.var[1][i] + u.var[2][i] * u.var[2][i] +
                         u.var[3][i] * u.var[3][i]) / rho;
      sound += gas.sound_speed(rho, p[i]);
      pm += p[i];
    }
    const double h = g.size[ue];
    raw[ue] = q_dif * h * h * h * 0.25 * (speed + sound) / (0.25 * pm) * std::abs(lap);
  }
  if (!smoothing) return;
  // 3. Nodal smoothing: nu_a = sum V_e nu_e / sum V_e (sum V_e = 4 M_a), nu_e = mean nu_a.
  work.nodal_viscosity.assign(std::size_t(nn), 0.0);
  for_each_element(loop, [&](Index e) {
    const auto ue = std::size_t(e);
    const double vn = g.volume[ue] * raw[ue];
    for (int a = 0; a < 4; ++a) work.nodal_viscosity[std::size_t(tets[4 * ue + std::size_t(a)])] += vn;
  });
#pragma omp parallel for schedule(static) if (nn > parallel_threshold)
  for (Index a = 0; a < nn; ++a)
    work.nodal_viscosity[std::size_t(a)] /= 4.0 * g.lumped_mass[std::size_t(a)];
#pragma omp parallel for schedule(static) if (ne > parallel_threshold)
  for (Index e = 0; e < ne; ++e) {
    const auto ue = std::size_t(e);
    double s = 0.0;
    for (int a = 0; a < 4; ++a) s += work.nodal_viscosity[std::size_t(tets[4 * ue + std::size_t(a)])];
    nu[ue] = 0.25 * s;
  }
}

}  // namespace shellflow::fluid
