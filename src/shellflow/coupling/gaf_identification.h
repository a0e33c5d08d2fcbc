#pragma once
// Identification of the generalised aerodynamic forces (GAF) from a forced-motion record
// (docs/flutter.md, "Identified aerodynamics"; ../design/identified_aero.md): the modal
// coordinates q_n the wall was moved by and the modal forces f_n the flow gave back, both
// sampled at the shell step dt with the coupled run's time stamps, fitted by a finite impulse
// response (a discrete Volterra kernel of first order)
//   f_n = sum_{j=0}^{L-1} H_j q_{n-j}      (q_n = 0 before the record)
// by least squares, optionally Tikhonov-regularised. H_0 is the instantaneous part a panel's
// GAF has (the piston-like wall pressure), so the model keeps it as its feedthrough D = H_0.
// The fit reports its relative residual: what the taps cannot explain (a memory longer than L
// steps, a nonlinear response, or a misaligned record).
#include <Eigen/Core>
#include <complex>
#include <vector>

namespace shellflow::coupling {

/// A discrete-time state-space model at step dt:
///   x_{n+1} = A x_n + B u_n,   y_n = C x_n + D u_n.
struct DiscreteStateSpace {
  double dt = 0.0;
  Eigen::MatrixXd A, B, C, D;
  Eigen::Index states() const { return A.rows(); }
  /// The transfer matrix C (z I - A)^-1 B + D at z (outputs x inputs).
  Eigen::MatrixXcd transfer(std::complex<double> z) const;
  /// The output sequence for an input sequence (rows = samples), from x_0 = 0.
  Eigen::MatrixXd simulate(const Eigen::MatrixXd& inputs) const;
};

/// A multi-input multi-output finite impulse response at step dt.
struct FirModel {
  double dt = 0.0;
  std::vector<Eigen::MatrixXd> taps;  ///< H_0 .. H_{L-1}, each outputs x inputs
  Eigen::Index inputs() const { return taps.empty() ? 0 : taps.front().cols(); }
  Eigen::Index outputs() const { return taps.empty() ? 0 : taps.front().rows(); }
  /// sum_j H_j z^-j (outputs x inputs).
  Eigen::MatrixXcd transfer(std::complex<double> z) const;
  /// The output sequence for an input sequence (rows = samples; inputs before it are 0).
  Eigen::MatrixXd simulate(const Eigen::MatrixXd& inputs) const;
  /// The same response as a state space whose state is the last L - 1 inputs (a shift
  /// register): (L - 1) * inputs() states, D = H_0.
  DiscreteStateSpace state_space() const;
};

struct FirFitOptions {
  int taps = 0;                 ///< L >= 1
  double regularisation = 0.0;  ///< Tikhonov weight, relative to the largest input energy
};

struct FirFit {
  FirModel model;
  double residual = 0.0;  ///< ||F - fitted||_F / ||F||_F over the record
  int samples = 0;
};

/// Fits an FIR to a record: `inputs` (samples x m, the modal coordinates), `outputs`
/// (samples x p, the modal forces), both at step dt and aligned sample by sample. Throws
/// InputError (one line naming the cause) when the record is shorter than the taps, holds
/// non-finite values, or an input carries no signal (its taps could not be determined).
FirFit fit_fir(const Eigen::MatrixXd& inputs, const Eigen::MatrixXd& outputs, double dt, const FirFitOptions& options);

}  // namespace shellflow::coupling
