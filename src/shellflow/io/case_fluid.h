#pragma once
// The `fluid` section of a case file as plain structs, part of case.h (which includes it;
// include case.h). Read by case_fluid.cpp; the keys are documented in docs/case-format.md.
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "shellflow/core/expression.h"
#include "shellflow/core/types.h"
#include "shellflow/io/yaml_reader.h"

namespace shellflow::io {

enum class ViscosityLaw { none, constant, sutherland, power };

/// Dynamic viscosity mu(T) and heat conduction k = mu c_p / Pr (Navier–Stokes runs).
struct Viscosity {
  ViscosityLaw law = ViscosityLaw::none;  ///< none: inviscid (Euler)
  double mu_ref = 1.716e-5;               ///< [Pa s] mu (constant) or mu at t_ref (Sutherland)
  double t_ref = 273.15;                  ///< [K]
  double sutherland = 110.4;              ///< Sutherland's constant S [K]
  double exponent = 0.76;                 ///< omega of the power law mu_ref (T / t_ref)^omega
  double prandtl = 0.72;
};

struct Gas {
  double gamma = 1.4;            ///< ratio of specific heats [-], > 1
  double gas_constant = 287.05;  ///< R [J/(kg K)], > 0
  Viscosity viscosity;
};

struct FreeStream {
  double density = 0.0;            ///< [kg/m^3], > 0
  double pressure = 0.0;           ///< [Pa], > 0
  double mach = 0.0;               ///< [-], >= 0
  Vec3 direction = Vec3::UnitX();  ///< unit vector (normalised when read)
};

enum class FluidBoundaryType { supersonic_inflow, supersonic_outflow, far_field, slip_wall, no_slip_wall, symmetry };

/// A scalar field written in a case file as a number or as an expression (expression.h) of
/// the node's initial coordinates x, y, z [m] and the time t [s].
///
/// With a `where` (the key it was read from, `case.yaml:12: fluid.analysis.initial.density`)
/// every evaluation checks its result: one that is not finite throws InputError naming the
/// key, the point, the time and the likely cause, so that a NaN or an overflow in an initial
/// state, a boundary state or a mesh motion stops the run where it enters.
class SpaceTimeScalar {
 public:
  SpaceTimeScalar() = default;
  explicit SpaceTimeScalar(Expression expression, std::string where = {})
      : expression_(std::move(expression)), where_(std::move(where)) {}
  double operator()(const Vec3& X, double t) const {
    const double point[4] = {X.x(), X.y(), X.z(), t};
    const double v = expression_.value(point);
    if (!where_.empty() && !std::isfinite(v)) fail_non_finite(X, t, v, false);
    return v;
  }
  /// Partial derivative with respect to t (exact: automatic differentiation).
  double time_derivative(const Vec3& X, double t) const {
    const double point[4] = {X.x(), X.y(), X.z(), t};
    const double d = expression_.evaluate(point, 3).derivative;
    if (!where_.empty() && !std::isfinite(d)) fail_non_finite(X, t, d, true);
    return d;
  }
  const Expression& expression() const { return expression_; }
  const std::string& where() const { return where_; }

 private:
  Expression expression_;
  std::string where_;  ///< empty: unchecked
  [[noreturn]] void fail_non_finite(const Vec3& X, double t, double value, bool is_derivative) const;
};

/// A gas state varying in space and time: density, velocity, pressure.
struct SpaceTimeState {
  SpaceTimeScalar density;
  std::array<SpaceTimeScalar, 3> velocity;
  SpaceTimeScalar pressure;
  SourceLocation where;
};

struct FluidBoundary {
  std::string group;  ///< physical group of the fluid mesh
  FluidBoundaryType type = FluidBoundaryType::slip_wall;
  /// Inflow / far-field state; absent: the free stream.
  std::optional<SpaceTimeState> state;
  /// No-slip walls [m/s], numbers or expressions of x, y, z, t (a profile at an inlet);
  /// absent: a fixed wall (on a moving mesh: the mesh's velocity).
  std::optional<std::array<SpaceTimeScalar, 3>> wall_velocity;
  std::optional<double> wall_temperature;  ///< no-slip walls [K]; absent: adiabatic
  SourceLocation where;                    ///< the list item `fluid.boundaries[i]`
};

/// A prescribed motion of every fluid node: x = X + d(X, t). The mesh velocity of a step is
/// (x^{n+1} - x^n) / dt, the choice that keeps a uniform flow exactly uniform; slip walls on
/// a moving mesh move with the mesh.
struct FluidMeshMotion {
  std::array<SpaceTimeScalar, 3> displacement;
  SourceLocation where;
};

/// A gas state given by density, velocity and pressure.
struct GasState {
  double density = 0.0;          ///< [kg/m^3], > 0
  Vec3 velocity = Vec3::Zero();  ///< [m/s]
  double pressure = 0.0;         ///< [Pa], > 0
};

/// Initial condition of a Riemann problem: `left` where (x - position n) . n < 0.
struct RiemannInitial {
  Vec3 normal = Vec3::UnitX();  ///< unit
  double position = 0.0;        ///< [m] along normal
  GasState left, right;
};

enum class FluidAnalysisType { transient, steady };

/// How slip walls are imposed (docs/fluid.md "Slip walls"): weak through the wall's flux
/// (default), or strong by projecting the nodal momentum (the paper's eq. 29).
enum class FluidSlipWalls { weak, strong };

struct FluidAnalysis {
  FluidAnalysisType type = FluidAnalysisType::transient;
  double cfl = 0.5;  ///< (0, 1] lumped mass, (0, 0.6] consistent
  int steps = 1000;  ///< steady: local time steps (at most)
  /// steady: stop once the density rate is below this fraction of its first-step value
  std::optional<double> residual_drop;
  double q_dif = 0.0;                  ///< artificial viscosity coefficient (paper eq. 28)
  int consistent_mass_iterations = 0;  ///< 0: lumped mass
  FluidSlipWalls slip_walls = FluidSlipWalls::weak;
  std::optional<RiemannInitial> riemann;  ///< initial state; absent: `initial` or the free stream
  std::optional<SpaceTimeState> initial;  ///< initial state as fields of x, y, z (t = 0)
  SourceLocation where;
};

/// How the gas acts on the shell in a coupled run.
enum class FluidModelType {
  euler,          ///< the flow solver on the fluid mesh (Euler or Navier–Stokes by gas.viscosity)
  piston_theory,  ///< first-order piston theory from the shell's motion (no fluid mesh)
};

struct FluidSection {
  FluidModelType model = FluidModelType::euler;
  Gas gas;
  FreeStream free_stream;
  std::vector<FluidBoundary> boundaries;
  std::optional<FluidMeshMotion> mesh_motion;  ///< absent: the mesh stays
  std::optional<FluidAnalysis> analysis;       ///< absent: the flow is not solved
};

}  // namespace shellflow::io
