#pragma once
// Linear flutter analysis (docs/flutter.md): the shell linearised about its flat reference
// state plus a linear aerodynamic model (modal_aerodynamics.h),
//   M q'' + K q = f,   f = C x + D0 q + D1 q',   x' = A x + B0 q + B1 q',
// e.g. first-order piston theory, f = -(qA A1 q + qD D1 q') with A1, D1 its matrices per unit
// coefficient (piston_theory.h) and
//   qA = rho U^2 / beta,   qD = rho U (M^2 - 2) / ((M^2 - 1) beta),   beta = sqrt(M^2 - 1).
// Solutions ~ exp(s t), s = sigma + i omega: the panel flutters when some sigma > 0.
//
// The eigenproblem is solved on a basis of the first `modes` in-vacuo modes (M-orthonormal,
// so M -> I and K -> diag(omega_k^2)): a 2K x 2K dense state matrix per parameter value,
// microseconds each. The full system (every free dof, the massless thickness parameter
// condensed out statically) is available for checking the truncation on small meshes: its
// dense state matrix is 2 n_mass wide, O(n^3) per value.
//
// Parameters (the conventions of Dowell, "Aeroelasticity of plates and shells", 1975):
//   lambda = rho U^2 a^3 / (beta D) = qA a^3 / D,   D = E h^3 / (12 (1 - nu^2)),
// a the panel length along the flow. A sweep in lambda keeps rho and M of the case (the
// aerodynamic damping grows like sqrt(lambda), Dowell's fixed mu/M), or drops the damping
// (mu/M -> 0, the classical coalescence values). A sweep in Mach keeps rho and p of the case
// (fixed altitude): U = M sqrt(gamma p / rho).
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <complex>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "shellflow/coupling/modal_aerodynamics.h"
#include "shellflow/shell/modal.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::coupling {

/// The reduced (or full) linear system of the shell, solved with any aerodynamic model given
/// in its coordinates.
class LinearFlutterSystem {
 public:
  /// `modes` > 0: a basis of that many in-vacuo modes; `modes` == 0: the full system.
  /// Throws InputError for supports along rotated directions (not handled yet) and
  /// SolverError when the supported stiffness is singular.
  LinearFlutterSystem(const shell::ShellModel& model, int modes, const shell::ModalOptions& options = {});

  /// A load matrix X on the shell's dofs (force -X u) in this system's coordinates:
  /// Phi^T X Phi on the modal basis, L^-1 X_mm L^-T on the full system (M_mm = L L^T).
  Eigen::MatrixXd generalised(const shell::SparseMatrix& X) const;

  /// The eigenvalues s with Im s >= 0 of the shell with this aerodynamic model, ordered by
  /// Im s, then Re s. A quasi-steady model: one per degree of freedom of the basis (complex
  /// pairs counted once, real roots by their larger half). A model with states: every root
  /// with Im s >= 0 (the structure's and the flow's).
  std::vector<std::complex<double>> eigenvalues(const AeroStateSpace& aero) const;
  /// max Re s (the growth rate of the least stable root) [1/s].
  double max_growth_rate(const AeroStateSpace& aero) const;

  /// The system on the first k modes of this modal basis (the truncation check).
  LinearFlutterSystem truncated(int k) const;

  /// The least stable root at these coefficients and its shape in the shell's dofs (modal
  /// basis only): the state matrix's eigenvector, q = Phi y, its phase turned so that the
  /// largest nodal displacement component is real and 1. Throws SolverError on the full
  /// system.
  std::pair<std::complex<double>, Eigen::VectorXcd> least_stable_mode(const AeroStateSpace& aero) const;
  /// The shell's dofs of modal coordinates y, Phi y, turned and scaled so that the largest
  /// nodal displacement component is real and 1 (modal basis only).
  Eigen::VectorXcd shape(const Eigen::VectorXcd& y) const;
  /// The in-vacuo modes of the basis, one column per mode (modal basis only; empty otherwise).
  const Eigen::MatrixXd& basis() const { return basis_; }

  Eigen::Index size() const { return static_cast<Eigen::Index>(K_.rows()); }
  /// The stiffness in this system's coordinates, where the mass is the identity.
  const Eigen::MatrixXd& stiffness() const { return K_; }
  bool modal() const { return modal_; }
  /// In-vacuo frequencies of the basis [Hz] (modal basis only; empty for the full system).
  const std::vector<double>& in_vacuo_frequencies() const { return frequencies_; }

 private:
  LinearFlutterSystem() = default;
  /// The state matrix [0 I 0; -K + D0, D1, C; B0, B1, A] (checked against the system's size).
  Eigen::MatrixXd state_matrix(const AeroStateSpace& aero) const;
  /// Throws SolverError when the model's blocks do not fit the system's size.
  void check_sizes(const AeroStateSpace& aero) const;
  Eigen::MatrixXd scaled(Eigen::MatrixXd X) const;  ///< L^-1 X L^-T (full system)

  bool modal_ = true;
  Eigen::MatrixXd K_;      ///< the stiffness in this system's coordinates (M -> I)
  Eigen::MatrixXd basis_;  ///< Phi: the in-vacuo modes in the shell's dofs (modal basis)
  std::vector<double> frequencies_;
  // Full system: the dofs with mass and the factor of their mass matrix.
  std::vector<Eigen::Index> mass_;
  Eigen::LLT<Eigen::MatrixXd> mass_factor_;
};

/// Orders roots by Im s, then Re s (the order of LinearFlutterSystem::eigenvalues).
void sort_roots(std::vector<std::complex<double>>& roots);

enum class FlutterParameter { lambda, mach };

/// The panel and flow quantities a sweep needs.
struct FlutterSetting {
  double length = 0.0;             ///< a: panel length along the flow [m]
  double bending_stiffness = 0.0;  ///< D [N m]
  double density = 0.0;            ///< rho_inf [kg/m^3]
  double pressure = 0.0;           ///< p_inf [Pa]
  double gamma = 1.4;
  double mach = 0.0;                ///< the case's Mach number
  bool aerodynamic_damping = true;  ///< false: mu/M -> 0 (lambda sweeps only)

  /// The flow at a parameter value (a Mach sweep at fixed rho and p; a lambda sweep at the
  /// case's rho and M, its speed from lambda).
  FlowCondition flow(FlutterParameter p, double value) const;
  double lambda_of_mach(double mach) const;  ///< at fixed rho, p
  /// The Mach number above sqrt(2) (where lambda grows with M) at fixed rho, p; NaN when
  /// lambda is below the minimum of lambda(M) (at M = sqrt(2)).
  double mach_of_lambda(double lambda) const;
  double mass_ratio_over_mach(double shell_density, double thickness) const;  ///< mu/M = rho a/(rho_m h M)
};

struct FlutterPoint {
  double value = 0.0;  ///< the parameter
  double lambda = 0.0, mach = 0.0;
  std::vector<std::complex<double>> eigenvalues;
  double scale = 0.0;  ///< max |s| of the roots kept (the round-off scale of sigma)
};

struct FlutterCritical {
  double value = 0.0;  ///< the parameter at the boundary
  double lambda = 0.0, mach = 0.0;
  double frequency_hz = 0.0;  ///< of the root that crosses
  int bisections = 0;
};

struct FlutterSweep {
  FlutterParameter parameter = FlutterParameter::lambda;
  std::vector<FlutterPoint> points;
  std::optional<FlutterCritical> critical;  ///< the lowest crossing in the range
};

/// Evaluates `points` equally spaced values in [lo, hi], then bisects the first interval
/// where the least stable root becomes unstable (sigma > 1e-8 max |s|) to a relative width
/// `relative_tolerance` of the parameter. `tracked_roots` > 0: only the that many roots of
/// lowest frequency count (and are kept in the points) — for the full system, whose highest
/// roots are the mesh's thickness-stretch modes. `on_value` (when given) is called after
/// each eigenvalue solve with the number of values solved so far (progress on large systems).
FlutterSweep sweep_flutter(const LinearFlutterSystem& system, const ModalAerodynamics& aero,
                           const FlutterSetting& setting, FlutterParameter parameter, double lo, double hi, int points,
                           double relative_tolerance = 1e-9, int tracked_roots = 0,
                           const std::function<void(int)>& on_value = {});

/// The seconds one dense nonsymmetric eigenvalue solve (values only) of size n x n takes on
/// this machine: a 200 x 200 solve timed here, scaled by (n / 200)^3.
double dense_eigenvalue_seconds(Eigen::Index n);

/// The panel length along `direction`: the extent of the shell's nodes.
double panel_length(const shell::ShellModel& model, const Vec3& direction);

std::string to_string(FlutterParameter p);

}  // namespace shellflow::coupling
