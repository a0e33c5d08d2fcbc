#include "shellflow/coupling/gaf_identification.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "shellflow/core/error.h"

namespace shellflow::coupling {

Eigen::MatrixXcd DiscreteStateSpace::transfer(std::complex<double> z) const {
  Eigen::MatrixXcd h = D.cast<std::complex<double>>();
  if (states() == 0) return h;
  const Eigen::MatrixXcd shifted = z * Eigen::MatrixXcd::Identity(states(), states()) - A.cast<std::complex<double>>();
  h += C.cast<std::complex<double>>() * shifted.partialPivLu().solve(B.cast<std::complex<double>>());
  return h;
}

Eigen::MatrixXd DiscreteStateSpace::simulate(const Eigen::MatrixXd& inputs) const {
  Eigen::MatrixXd out(inputs.rows(), D.rows());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(states());
  for (Eigen::Index n = 0; n < inputs.rows(); ++n) {
    const Eigen::VectorXd u = inputs.row(n).transpose();
    out.row(n) = (C * x + D * u).transpose();  // C x is a zero vector without states
    x = A * x + B * u;
  }
  return out;
}

Eigen::MatrixXcd FirModel::transfer(std::complex<double> z) const {
  Eigen::MatrixXcd h = Eigen::MatrixXcd::Zero(outputs(), inputs());
  std::complex<double> power = 1.0;  // z^-j
  for (const Eigen::MatrixXd& tap : taps) {
    h += power * tap.cast<std::complex<double>>();
    power /= z;
  }
  return h;
}

Eigen::MatrixXd FirModel::simulate(const Eigen::MatrixXd& inputs) const {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(inputs.rows(), outputs());
  for (Eigen::Index n = 0; n < inputs.rows(); ++n)
    for (Eigen::Index j = 0; j < Eigen::Index(taps.size()) && j <= n; ++j)
      out.row(n) += (taps[std::size_t(j)] * inputs.row(n - j).transpose()).transpose();
  return out;
}

DiscreteStateSpace FirModel::state_space() const {
  const Eigen::Index m = inputs(), p = outputs(), L = Eigen::Index(taps.size());
  const Eigen::Index n = std::max<Eigen::Index>(L - 1, 0) * m;
  DiscreteStateSpace s;
  s.dt = dt;
  s.A = Eigen::MatrixXd::Zero(n, n);
  s.B = Eigen::MatrixXd::Zero(n, m);
  s.C = Eigen::MatrixXd::Zero(p, n);
  s.D = L > 0 ? taps.front() : Eigen::MatrixXd::Zero(p, m);
  if (n == 0) return s;
  // x_n = [u_{n-1}; ...; u_{n-L+1}]: the next state shifts it down and puts u_n on top.
  s.B.topRows(m).setIdentity();
  for (Eigen::Index k = 1; k + 1 < L; ++k) s.A.block(k * m, (k - 1) * m, m, m).setIdentity();
  for (Eigen::Index j = 1; j < L; ++j) s.C.middleCols((j - 1) * m, m) = taps[std::size_t(j)];
  return s;
}

namespace {

void check_record(const Eigen::MatrixXd& inputs, const Eigen::MatrixXd& outputs, double dt, int taps) {
  if (taps < 1) throw InputError(fmt::format("GAF identification: {} taps; give at least 1", taps));
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw InputError(fmt::format("GAF identification: the step dt = {} s must be positive", dt));
  if (inputs.rows() != outputs.rows())
    throw InputError(
        fmt::format("GAF identification: {} motion samples but {} force samples; the record must "
                    "hold both at every shell step",
                    inputs.rows(), outputs.rows()));
  if (inputs.cols() == 0 || outputs.cols() == 0) throw InputError("GAF identification: the record holds no modes");
  const Eigen::Index unknowns = Eigen::Index(taps) * inputs.cols();
  if (inputs.rows() < unknowns)
    throw InputError(
        fmt::format("GAF identification: {} samples cannot determine {} taps of {} modes ({} "
                    "unknowns per force); lengthen the forced motion or use fewer taps",
                    inputs.rows(), taps, inputs.cols(), unknowns));
  if (!inputs.allFinite() || !outputs.allFinite())
    throw InputError("GAF identification: the record holds a value that is not finite");
  for (Eigen::Index k = 0; k < inputs.cols(); ++k)
    if (inputs.col(k).cwiseAbs().maxCoeff() == 0.0)
      throw InputError(
          fmt::format("GAF identification: mode {} was never moved (its coordinate is 0 throughout "
                      "the record); give it a pulse of its own",
                      k + 1));
}

}  // namespace

FirFit fit_fir(const Eigen::MatrixXd& inputs, const Eigen::MatrixXd& outputs, double dt, const FirFitOptions& options) {
  const int L = options.taps;
  check_record(inputs, outputs, dt, L);
  const Eigen::Index N = inputs.rows(), m = inputs.cols(), p = outputs.cols(), unknowns = Eigen::Index(L) * m;
  // The regression: row n = [q_n^T, q_{n-1}^T, ..., q_{n-L+1}^T], zero before the record.
  const bool regularised = options.regularisation > 0.0;
  Eigen::MatrixXd phi = Eigen::MatrixXd::Zero(N + (regularised ? unknowns : 0), unknowns);
  for (Eigen::Index n = 0; n < N; ++n)
    for (Eigen::Index j = 0; j < L && j <= n; ++j) phi.block(n, j * m, 1, m) = inputs.row(n - j);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(phi.rows(), p);
  rhs.topRows(N) = outputs;
  if (regularised) {
    const double energy = inputs.colwise().squaredNorm().maxCoeff();
    phi.bottomRows(unknowns).diagonal().setConstant(std::sqrt(options.regularisation * energy));
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(phi);
  if (qr.rank() < unknowns)
    throw InputError(
        fmt::format("GAF identification: the motions determine only {} of the {} tap values per "
                    "force (modes moved together, or pulses too smooth for {} taps); stagger the "
                    "pulses, shorten them, or regularise",
                    qr.rank(), unknowns, L));
  const Eigen::MatrixXd theta = qr.solve(rhs);
  FirFit fit;
  fit.samples = int(N);
  fit.model.dt = dt;
  for (Eigen::Index j = 0; j < L; ++j) fit.model.taps.push_back(theta.middleRows(j * m, m).transpose());
  const double size = outputs.norm();
  fit.residual = size > 0.0 ? (outputs - phi.topRows(N) * theta).norm() / size : 0.0;
  return fit;
}

}  // namespace shellflow::coupling
