#pragma once
// Strain and stress recovery for output (shell.md §2.5, §3): at a point (element, ξ1, ξ2,
// ξ3) and averaged at the nodes. The kinematics are the kernel's (shell_element.h), so the
// values are those the internal force integrates: Green–Lagrange E in the global frame,
// second Piola–Kirchhoff S = λ tr(E) I + 2μ E (full 3-D SVK; the transverse strain carried
// by |G| and `a` lets S33 relax to ≈ 0), Cauchy σ = J⁻¹ F S Fᵀ.
#include <vector>

#include "shellflow/shell/shell_queries.h"

namespace shellflow::shell {

enum class StressMeasure { green_lagrange_strain, second_piola_kirchhoff, cauchy };

/// Thickness position ξ3 of an output surface (−1, 0, 1); `top` is the +V side.
enum class SurfaceSide { bottom = -1, middle = 0, top = 1 };

/// Everything at one material point of the shell volume.
struct StressPoint {
  Mat3 F = Mat3::Identity();  ///< deformation gradient A = A1 A0⁻¹
  Mat3 E = Mat3::Zero();      ///< Green–Lagrange strain
  Mat3 S = Mat3::Zero();      ///< second Piola–Kirchhoff stress
  Mat3 sigma = Mat3::Zero();  ///< Cauchy stress
};

/// Strain and stresses at (p.element, p.xi, xi3), xi3 in [−1, 1], at increments u.
/// Throws InputError for a missing element and SolverError when det F <= 0 there.
StressPoint stress_at(const ShellModel& model, const Eigen::VectorXd& u, const ShellPoint& p, double xi3);

/// The tensor of `measure` at a stress point.
const Mat3& select(const StressPoint& s, StressMeasure measure);

/// von Mises equivalent sqrt(3/2 dev(T):dev(T)) of a symmetric tensor.
double von_mises(const Mat3& T);

/// Per node: the tensor of a measure on one surface, averaged with equal weights over the
/// elements around the node (each evaluated at the node's own parametric point), and the
/// von Mises value of that average (for VTU point data).
struct NodalStresses {
  std::vector<Mat3> tensor;
  std::vector<double> von_mises;
};
NodalStresses nodal_stresses(const ShellModel& model, const Eigen::VectorXd& u, StressMeasure measure,
                             SurfaceSide side);

}  // namespace shellflow::shell
