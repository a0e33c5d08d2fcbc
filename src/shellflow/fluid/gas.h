#pragma once
// Ideal gas closure and the conversions between primitive and conservative states.
#include <cmath>

#include "shellflow/core/types.h"

namespace shellflow::fluid {

/// Calorically perfect gas: p = (gamma - 1) rho e, T = p / (rho R).
struct IdealGas {
  double gamma = 1.4;
  double gas_constant = 287.05;  ///< R in J/(kg K)

  double pressure(double rho, double mx, double my, double mz, double energy) const {
    return (gamma - 1.0) * (energy - 0.5 * (mx * mx + my * my + mz * mz) / rho);
  }
  double sound_speed(double rho, double p) const { return std::sqrt(gamma * p / rho); }
  double temperature(double rho, double p) const { return p / (rho * gas_constant); }
};

/// rho, velocity, pressure.
struct Primitive {
  double rho = 1.0;
  Vec3 velocity = Vec3::Zero();
  double pressure = 1.0;
};

/// rho, momentum rho u, total energy per volume rho E.
struct Conservative {
  double rho = 1.0;
  Vec3 momentum = Vec3::Zero();
  double energy = 1.0;
};

inline Conservative to_conservative(const IdealGas& gas, const Primitive& w) {
  return {w.rho, w.rho * w.velocity,
          w.pressure / (gas.gamma - 1.0) + 0.5 * w.rho * w.velocity.squaredNorm()};
}

inline Primitive to_primitive(const IdealGas& gas, const Conservative& q) {
  return {q.rho, q.momentum / q.rho,
          gas.pressure(q.rho, q.momentum.x(), q.momentum.y(), q.momentum.z(), q.energy)};
}

}  // namespace shellflow::fluid
