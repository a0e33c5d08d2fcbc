#pragma once
// Nodal conservative state stored as a structure of arrays: one contiguous array per
// variable, so the element loop streams each variable and node loops vectorise.
#include <array>
#include <vector>

#include "shellflow/core/types.h"
#include "shellflow/fluid/gas.h"

namespace shellflow::fluid {

inline constexpr int num_variables = 5;  ///< rho, rho u_x, rho u_y, rho u_z, rho E
enum Variable : int { rho_var = 0, mx_var = 1, my_var = 2, mz_var = 3, energy_var = 4 };

struct FluidState {
  std::array<std::vector<double>, num_variables> var;

  Index size() const { return static_cast<Index>(var[0].size()); }
  void resize(Index n) {
    for (auto& v : var) v.assign(static_cast<std::size_t>(n), 0.0);
  }
  void fill_zero() {
    for (auto& v : var) std::fill(v.begin(), v.end(), 0.0);
  }
  Conservative get(Index a) const {
    const auto i = static_cast<std::size_t>(a);
    return {var[0][i], Vec3(var[1][i], var[2][i], var[3][i]), var[4][i]};
  }
  void set(Index a, const Conservative& q) {
    const auto i = static_cast<std::size_t>(a);
    var[0][i] = q.rho;
    var[1][i] = q.momentum.x();
    var[2][i] = q.momentum.y();
    var[3][i] = q.momentum.z();
    var[4][i] = q.energy;
  }
};

}  // namespace shellflow::fluid
