#pragma once
// First-order piston theory at the shell's load points (coupling.md; Ashley & Zartarian):
//   dp = (rho U^2 / beta) [ dw/dx + (M^2 - 2)/(M^2 - 1) (1/U) dw/dt ],  beta = sqrt(M^2 - 1),
// the pressure rise over p_inf on the wetted face, w the displacement along the wetted face's
// normal into the flow, x along the flow. Evaluated from the shell's own motion (no fluid
// mesh): w and dw/dt from the nodal displacement and velocity interpolated at the load point,
// dw/dx from the surface gradient of the displacement in the reference configuration.
//
// The same operator as linear matrices on the shell's dofs: the shell feels the follower
// pressure -sign_k dp_k along its normal N_k (oriented like V); linearised about the flat
// reference, F = -(A u + D v) with (3x3 blocks on the position rows)
//   A_jl = (rho U^2 / beta) sum_k w_k phi_j phi_l,x N_k N_k^T,
//   D_jl = (rho U c / beta) sum_k w_k phi_j phi_l   N_k N_k^T,   c = (M^2 - 2)/(M^2 - 1),
// independent of which face is wetted (sign_k^2 = 1). A is not symmetric: it is what makes
// the panel flutter.
#include <Eigen/Core>
#include <span>
#include <vector>

#include "shellflow/core/types.h"
#include "shellflow/coupling/load_point_basis.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::coupling {

/// Validity limits (docs/coupling.md, "Piston theory"): the lowest Mach number accepted
/// (below it the stream over the panel is transonic and 1/beta grows without bound), and the
/// largest sine of the angle between the stream and the panel (a stream along the panel).
inline constexpr double kPistonTheoryMinMach = 1.2;
inline constexpr double kPistonTheoryMaxIncidence = 0.02;  // about 1.15 degrees

struct PistonTheoryFlow {
  double density = 0.0;             ///< rho_inf [kg/m^3]
  double speed = 0.0;               ///< U [m/s]
  double mach = 0.0;                ///< M > 1
  Vec3 direction = Vec3::UnitX();   ///< unit flow direction (tangent to the panel)
  Vec3 wet_normal = Vec3::UnitY();  ///< points from the shell into the flow (picks the wetted face)
};

class PistonTheory {
 public:
  /// Throws InputError for M < kPistonTheoryMinMach, a non-positive density or speed, a wet
  /// normal within 30 degrees of the panel's plane at a load point, a stream more than
  /// kPistonTheoryMaxIncidence (sine) off the panel's mean plane.
  PistonTheory(const shell::ShellModel& model, PistonTheoryFlow flow);

  /// dp_k at every load point of the shell state (u, v).
  void pressure_rise(const Eigen::VectorXd& u, const Eigen::VectorXd& v, std::span<double> dp) const;
  /// A and D on the pattern of model.make_matrix().
  void matrices(shell::SparseMatrix& stiffness, shell::SparseMatrix& damping) const;
  /// The same with other coefficients in place of rho U^2 / beta and rho U c / beta (1 and 1:
  /// the matrices per unit coefficient, as the linear flutter analysis scales them).
  void matrices(shell::SparseMatrix& stiffness, shell::SparseMatrix& damping, double q_stiffness,
                double q_damping) const;
  /// Per load point: +1 where the shell normal (like V) points into the flow, -1 elsewhere.
  const std::vector<double>& sign() const { return sign_; }
  const PistonTheoryFlow& flow() const { return flow_; }
  /// rho U^2 / beta and rho U c / beta.
  double stiffness_coefficient() const { return q_stiffness_; }
  double damping_coefficient() const { return q_damping_; }

 private:
  void check_geometry(std::span<const shell::LoadPoint> points) const;

  const shell::ShellModel& model_;
  PistonTheoryFlow flow_;
  double q_stiffness_ = 0.0, q_damping_ = 0.0;
  LoadPointBasis basis_;
  std::vector<double> dphi_dx_;  ///< n per load point: surface derivative along the flow
  std::vector<Vec3> normal_;     ///< wetted-face normal sign_k N_k (into the flow)
  std::vector<double> sign_;
};

}  // namespace shellflow::coupling
