#pragma once
// The linear flutter analysis with a discrete-time aerodynamic model (an identified GAF,
// gaf_identification.h): the coupled system advanced by one shell step,
//   structure  M q'' + K q = f  by Newmark's average acceleration at the model's step dt
//              (the scheme of every shellflow shell run, M -> I in the system's coordinates),
//   flow       x_{n+1} = A x_n + B q_n,   f_n = scale (C x_n + D q_n),
// is the linear map Y_{n+1} = T Y_n on Y = [q; q'; x]. Its eigenvalues z give the roots
// s = ln(z) / dt; the panel flutters when some |z| > 1. Unlike a conversion of the model to
// continuous time (which would delay its forces by half a step, ../design/identified_aero.md),
// the model meets the structure with the sampling it was identified with. `scale` multiplies
// the forces: rho U^2 / beta over the identification's, exact for a density (lambda) sweep at
// the identification's Mach number.
#include <complex>
#include <vector>

#include "shellflow/coupling/gaf_identification.h"
#include "shellflow/coupling/linear_flutter.h"

namespace shellflow::coupling {

/// T: the one-step map on [q; q'; x] (2 n + states wide). Throws SolverError when the model's
/// sizes do not fit the system or its step is not positive.
Eigen::MatrixXd discrete_step_matrix(const LinearFlutterSystem& system, const DiscreteStateSpace& aero, double scale);

/// The roots s = ln(z) / dt with Im s >= 0 of T's eigenvalues z != 0, ordered by Im s, then
/// Re s (a z on the negative real axis gives Im s = pi / dt).
std::vector<std::complex<double>> discrete_eigenvalues(const LinearFlutterSystem& system,
                                                       const DiscreteStateSpace& aero, double scale);

}  // namespace shellflow::coupling
