#pragma once
// Ideal gas closure, the viscosity law of Navier–Stokes runs, and the conversions between
// primitive and conservative states.
#include <cmath>

#include "shellflow/core/types.h"

namespace shellflow::fluid {

/// Dynamic viscosity mu(T) and conductivity k = mu c_p / Pr (fluid.md §1).
enum class ViscosityLaw {
  none,        ///< Euler: no viscous or conduction terms (the viscous pass is skipped)
  constant,    ///< mu = mu_ref
  sutherland,  ///< mu = mu_ref (T / T_ref)^{3/2} (T_ref + S) / (T + S)
  power,       ///< mu = mu_ref (T / T_ref)^omega (omega = 1: Chapman-Rubesin C = rho mu / (rho_e mu_e) = 1)
};
const char* to_string(ViscosityLaw law);

struct Viscosity {
  ViscosityLaw law = ViscosityLaw::none;
  double mu_ref = 1.716e-5;   ///< Pa s: the constant mu, or Sutherland's mu at t_ref (air)
  double t_ref = 273.15;      ///< K, Sutherland reference temperature (air)
  double sutherland = 110.4;  ///< K, Sutherland constant S (air)
  double exponent = 0.76;     ///< omega of the power law (air near 300 K: about 0.76)
  double prandtl = 0.72;

  bool viscous() const { return law != ViscosityLaw::none; }
  /// mu at temperature T (0 for Euler).
  double dynamic(double temperature) const {
    switch (law) {
      case ViscosityLaw::none:
        return 0.0;
      case ViscosityLaw::constant:
        return mu_ref;
      case ViscosityLaw::sutherland: {
        const double r = temperature / t_ref;
        return mu_ref * r * std::sqrt(r) * (t_ref + sutherland) / (temperature + sutherland);
      }
      case ViscosityLaw::power:
        return exponent == 1.0 ? mu_ref * (temperature / t_ref) : mu_ref * std::pow(temperature / t_ref, exponent);
    }
    return 0.0;
  }
};

/// Calorically perfect gas: p = (gamma - 1) rho e, T = p / (rho R).
struct IdealGas {
  double gamma = 1.4;
  double gas_constant = 287.05;  ///< R in J/(kg K)
  Viscosity viscosity;           ///< default: inviscid (Euler)

  IdealGas() = default;
  IdealGas(double ratio_of_specific_heats, double r, Viscosity law = {})
      : gamma(ratio_of_specific_heats), gas_constant(r), viscosity(law) {}

  double pressure(double rho, double mx, double my, double mz, double energy) const {
    return (gamma - 1.0) * (energy - 0.5 * (mx * mx + my * my + mz * mz) / rho);
  }
  double sound_speed(double rho, double p) const { return std::sqrt(gamma * p / rho); }
  double temperature(double rho, double p) const { return p / (rho * gas_constant); }
  double cp() const { return gamma * gas_constant / (gamma - 1.0); }
  double cv() const { return gas_constant / (gamma - 1.0); }
  bool viscous() const { return viscosity.viscous(); }
  /// Thermal conductivity k = mu c_p / Pr for the dynamic viscosity mu.
  double conductivity(double mu) const { return mu * cp() / viscosity.prandtl; }
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
  return {w.rho, w.rho * w.velocity, w.pressure / (gas.gamma - 1.0) + 0.5 * w.rho * w.velocity.squaredNorm()};
}

inline Primitive to_primitive(const IdealGas& gas, const Conservative& q) {
  return {q.rho, q.momentum / q.rho, gas.pressure(q.rho, q.momentum.x(), q.momentum.y(), q.momentum.z(), q.energy)};
}

}  // namespace shellflow::fluid
