#include "shellflow/fluid/mass.h"

namespace shellflow::fluid {

void apply_consistent_mass(const ElementLoop& loop, const TetGeometry& g, const FluidState& x, FluidState& out) {
  out.fill_zero();
  for_each_element(loop, [&](Index e) {
    const auto ue = std::size_t(e);
    const Index* n = loop.tets.data() + 4 * ue;
    const double c = g.volume[ue] / 20.0;
    for (int v = 0; v < num_variables; ++v) {
      const auto& xv = x.var[std::size_t(v)];
      auto& ov = out.var[std::size_t(v)];
      const double sum = xv[std::size_t(n[0])] + xv[std::size_t(n[1])] + xv[std::size_t(n[2])] + xv[std::size_t(n[3])];
      for (int a = 0; a < 4; ++a) ov[std::size_t(n[a])] += c * (xv[std::size_t(n[a])] + sum);
    }
  });
}

void solve_consistent_mass(const ElementLoop& loop, const TetGeometry& g, const FluidState& r, int iterations,
                           FluidState& dx, FluidState& work, const std::function<void(FluidState&)>& reimpose) {
  const Index nn = r.size();
  const auto& m = g.lumped_mass;
  for (int v = 0; v < num_variables; ++v)
    for (Index a = 0; a < nn; ++a)
      dx.var[std::size_t(v)][std::size_t(a)] = r.var[std::size_t(v)][std::size_t(a)] / m[std::size_t(a)];
  if (reimpose) reimpose(dx);
  for (int k = 0; k < iterations; ++k) {
    apply_consistent_mass(loop, g, dx, work);
    for (int v = 0; v < num_variables; ++v) {
      auto& d = dx.var[std::size_t(v)];
      const auto& rv = r.var[std::size_t(v)];
      const auto& mc = work.var[std::size_t(v)];
      for_each_node(
          nn, [&](Index a) { d[std::size_t(a)] += (rv[std::size_t(a)] - mc[std::size_t(a)]) / m[std::size_t(a)]; });
    }
    if (reimpose) reimpose(dx);
  }
}

}  // namespace shellflow::fluid
