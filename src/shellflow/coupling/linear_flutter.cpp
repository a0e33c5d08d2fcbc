#include "shellflow/coupling/linear_flutter.h"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include "shellflow/core/error.h"

namespace shellflow::coupling {

namespace {

Eigen::MatrixXd restrict(const shell::SparseMatrix& S, const std::vector<Eigen::Index>& rows,
                         const std::vector<Eigen::Index>& cols) {
  const Eigen::MatrixXd dense(S);
  Eigen::MatrixXd out(Eigen::Index(rows.size()), Eigen::Index(cols.size()));
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = 0; j < cols.size(); ++j) out(Eigen::Index(i), Eigen::Index(j)) = dense(rows[i], cols[j]);
  return out;
}

}  // namespace

LinearFlutterSystem::LinearFlutterSystem(const shell::ShellModel& model, int modes, const shell::ModalOptions& options)
    : modal_(modes > 0) {
  if (model.has_local_frames())
    throw_input_error(
        "linear flutter analysis: supports along rotated directions are not supported yet; "
        "use supports along the global axes");
  if (modal_) {
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
    const shell::ModalResult m = shell::natural_frequencies(model, modes, zero, options);
    Eigen::MatrixXd Phi(model.num_dofs(), modes);
    for (int i = 0; i < modes; ++i) Phi.col(i) = m.modes[std::size_t(i)];
    frequencies_ = m.frequencies;
    K_ = Eigen::MatrixXd::Zero(modes, modes);
    for (int i = 0; i < modes; ++i) K_(i, i) = std::pow(2.0 * std::numbers::pi * m.frequencies[std::size_t(i)], 2);
    basis_ = std::move(Phi);
    return;
  }
  // Full system: the free dofs that carry mass (positions, directors) keep their rows; the
  // massless ones (the thickness parameter, shell.md §6) are condensed out of K. Aerodynamic
  // loads (piston theory's, the flow's) load and read positions only, so they need no
  // condensation.
  shell::SparseMatrix K = model.make_matrix(), M = model.make_matrix();
  Eigen::VectorXd f;
  model.assemble(Eigen::VectorXd::Zero(model.num_dofs()), f, &K);
  model.assemble_mass(M);
  const auto& fixed = model.constrained();
  const Eigen::VectorXd diag = M.diagonal();
  std::vector<Eigen::Index> massless;
  for (Eigen::Index i = 0; i < model.num_dofs(); ++i) {
    if (fixed[std::size_t(i)]) continue;
    (diag(i) > 0.0 ? mass_ : massless).push_back(i);
  }
  Eigen::MatrixXd Kmm = restrict(K, mass_, mass_);
  if (!massless.empty()) {
    const Eigen::MatrixXd Kma = restrict(K, mass_, massless);
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(restrict(K, massless, massless));
    Kmm -= Kma * lu.solve(Kma.transpose());
  }
  // M = L L^T: with q = L^-T y the mass becomes the identity.
  mass_factor_.compute(restrict(M, mass_, mass_));
  if (mass_factor_.info() != Eigen::Success)
    throw SolverError("linear flutter analysis: the mass matrix of the free dofs is not positive definite");
  K_ = scaled(Kmm);
}

Eigen::MatrixXd LinearFlutterSystem::scaled(Eigen::MatrixXd X) const {
  mass_factor_.matrixL().solveInPlace(X);
  X.transposeInPlace();
  mass_factor_.matrixL().solveInPlace(X);
  return Eigen::MatrixXd(X.transpose());  // L^-1 X L^-T
}

Eigen::MatrixXd LinearFlutterSystem::generalised(const shell::SparseMatrix& X) const {
  if (modal_) return basis_.transpose() * (X * basis_);
  return scaled(restrict(X, mass_, mass_));
}

LinearFlutterSystem LinearFlutterSystem::truncated(int k) const {
  if (!modal_ || k < 1 || k > K_.rows())
    throw SolverError(fmt::format("linear flutter analysis: cannot truncate a {} system of {} to {} modes",
                                  modal_ ? "modal" : "full", K_.rows(), k));
  LinearFlutterSystem t;
  t.K_ = K_.topLeftCorner(k, k);
  t.frequencies_.assign(frequencies_.begin(), frequencies_.begin() + k);
  t.basis_ = basis_.leftCols(k);
  return t;
}

void LinearFlutterSystem::check_sizes(const AeroStateSpace& aero) const {
  const Eigen::Index n = K_.rows(), m = aero.states();
  const auto check = [&](const Eigen::MatrixXd& X, Eigen::Index rows, Eigen::Index cols, const char* name) {
    if (X.rows() != rows || X.cols() != cols)
      throw SolverError(fmt::format("linear flutter analysis: the aerodynamic model's {} is {} x {}, not {} x {}", name,
                                    X.rows(), X.cols(), rows, cols));
  };
  check(aero.D0, n, n, "D0");
  check(aero.D1, n, n, "D1");
  if (m > 0) {
    check(aero.A, m, m, "A");
    check(aero.B0, m, n, "B0");
    check(aero.B1, m, n, "B1");
    check(aero.C, n, m, "C");
  }
}

Eigen::MatrixXd LinearFlutterSystem::state_matrix(const AeroStateSpace& aero) const {
  check_sizes(aero);
  const Eigen::Index n = K_.rows(), m = aero.states();
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(2 * n + m, 2 * n + m);
  S.block(0, n, n, n).setIdentity();
  S.block(n, 0, n, n) = -K_ + aero.D0;
  S.block(n, n, n, n) = aero.D1;
  if (m > 0) {
    S.block(n, 2 * n, n, m) = aero.C;
    S.block(2 * n, 0, m, n) = aero.B0;
    S.block(2 * n, n, m, n) = aero.B1;
    S.block(2 * n, 2 * n, m, m) = aero.A;
  }
  return S;
}

std::pair<std::complex<double>, Eigen::VectorXcd> LinearFlutterSystem::least_stable_mode(
    const AeroStateSpace& aero) const {
  if (!modal_) throw SolverError("linear flutter analysis: mode shapes need the modal basis (not --direct)");
  const Eigen::Index n = K_.rows();
  const Eigen::EigenSolver<Eigen::MatrixXd> es(state_matrix(aero), true);
  if (es.info() != Eigen::Success) throw SolverError("linear flutter analysis: the eigenvalue solver failed");
  // The least stable root with Im s >= 0 (its conjugate carries the same shape).
  Eigen::Index best = -1;
  for (Eigen::Index k = 0; k < es.eigenvalues().size(); ++k) {
    const auto z = es.eigenvalues()(k);
    if (z.imag() >= 0.0 && (best < 0 || z.real() > es.eigenvalues()(best).real())) best = k;
  }
  return {es.eigenvalues()(best), shape(es.eigenvectors().col(best).head(n))};
}

Eigen::VectorXcd LinearFlutterSystem::shape(const Eigen::VectorXcd& y) const {
  if (!modal_) throw SolverError("linear flutter analysis: mode shapes need the modal basis (not --direct)");
  Eigen::VectorXcd shape = basis_.cast<std::complex<double>>() * y;
  Eigen::Index largest = 0;
  double peak = -1.0;
  for (Eigen::Index i = 0; i < shape.size(); ++i)
    if (i % shell::dofs_per_node < 3 && std::abs(shape(i)) > peak) peak = std::abs(shape(largest = i));
  if (peak > 0.0) shape /= shape(largest);
  return shape;
}

std::vector<std::complex<double>> LinearFlutterSystem::eigenvalues(const AeroStateSpace& aero) const {
  const Eigen::Index n = K_.rows(), m = aero.states();
  Eigen::MatrixXd S;
  const bool inverted = !modal_;
  if (modal_) {
    S = state_matrix(aero);
  } else if (m == 0) {
    // The full system's roots span ~1e3 to ~1e7 rad/s: the QR iteration's error ~ eps ||S||
    // would swamp the panel's roots. Its inverse [Kq^-1 D1, -Kq^-1; I, 0] (Kq = K - D0) has
    // them as its largest eigenvalues 1/s, to round-off relative to themselves.
    check_sizes(aero);
    S = Eigen::MatrixXd::Zero(2 * n, 2 * n);
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(K_ - aero.D0);
    S.topLeftCorner(n, n) = lu.solve(aero.D1);
    S.topRightCorner(n, n) = -lu.inverse();
    S.bottomLeftCorner(n, n).setIdentity();
  } else {
    // With flow states: the same inversion, of the whole state matrix.
    S = Eigen::PartialPivLU<Eigen::MatrixXd>(state_matrix(aero)).inverse();
  }
  const Eigen::EigenSolver<Eigen::MatrixXd> es(S, false);
  if (es.info() != Eigen::Success) throw SolverError("linear flutter analysis: the eigenvalue solver failed");
  std::vector<std::complex<double>> s;
  for (const auto& z : es.eigenvalues()) s.push_back(inverted ? 1.0 / z : z);
  std::sort(s.begin(), s.end(), [](const auto& a, const auto& b) {
    return a.imag() != b.imag() ? a.imag() > b.imag() : a.real() > b.real();
  });
  if (m == 0) {
    s.resize(std::size_t(n));  // one root per dof: the n of largest Im s (a real pair keeps its larger root)
  } else {
    s.erase(std::find_if(s.begin(), s.end(), [](const auto& z) { return z.imag() < 0.0; }), s.end());
  }
  sort_roots(s);
  return s;
}

void sort_roots(std::vector<std::complex<double>>& roots) {
  std::sort(roots.begin(), roots.end(), [](const auto& a, const auto& b) {
    return a.imag() != b.imag() ? a.imag() < b.imag() : a.real() < b.real();
  });
}

double LinearFlutterSystem::max_growth_rate(const AeroStateSpace& aero) const {
  double best = -std::numeric_limits<double>::infinity();
  for (const auto& s : eigenvalues(aero)) best = std::max(best, s.real());
  return best;
}

FlowCondition FlutterSetting::flow(FlutterParameter p, double value) const {
  const double m = p == FlutterParameter::mach ? value : mach;
  const double m2 = m * m, beta = std::sqrt(m2 - 1.0);
  FlowCondition f;
  f.density = density;
  f.mach = m;
  if (p == FlutterParameter::mach) {
    f.speed = m * std::sqrt(gamma * pressure / density);
    f.dynamic_pressure_over_beta = density * f.speed * f.speed / beta;
    return f;
  }
  // lambda at the case's rho and M: U from qA = rho U^2 / beta.
  f.dynamic_pressure_over_beta = value * bending_stiffness / std::pow(length, 3);
  f.speed = std::sqrt(std::max(f.dynamic_pressure_over_beta, 0.0) * beta / density);
  f.damping = aerodynamic_damping;
  return f;
}

double FlutterSetting::lambda_of_mach(double m) const {
  return gamma * pressure * m * m / std::sqrt(m * m - 1.0) * std::pow(length, 3) / bending_stiffness;
}

double FlutterSetting::mach_of_lambda(double lambda) const {
  // lambda(M) = k M^2 / sqrt(M^2 - 1), k = gamma p a^3 / D: with x = M^2 - 1,
  // (x + 1)^2 = (lambda / k)^2 x, the root x >= 1 (M >= sqrt 2).
  const double r = lambda / (gamma * pressure * std::pow(length, 3) / bending_stiffness);
  const double b = r * r - 2.0;  // x^2 - b x + 1 = 0
  if (!(b >= 2.0)) return std::numeric_limits<double>::quiet_NaN();
  const double x = 0.5 * (b + std::sqrt(b * b - 4.0));
  return std::sqrt(x + 1.0);
}

double FlutterSetting::mass_ratio_over_mach(double shell_density, double thickness) const {
  return density * length / (shell_density * thickness * mach);
}

FlutterSweep sweep_flutter(const LinearFlutterSystem& system, const ModalAerodynamics& aero,
                           const FlutterSetting& setting, FlutterParameter parameter, double lo, double hi, int points,
                           double relative_tolerance, int tracked_roots, const std::function<void(int)>& on_value) {
  if (!(hi > lo) || points < 2)
    throw_input_error(
        "linear flutter analysis: the range [{}, {}] with {} points is empty; give lo < hi "
        "and at least 2 points",
        lo, hi, points);
  FlutterSweep sweep;
  sweep.parameter = parameter;
  int solved = 0;
  const auto evaluate = [&](double value) {
    FlutterPoint p;
    p.value = value;
    p.eigenvalues = aero.roots(system, setting.flow(parameter, value));
    if (tracked_roots > 0 && p.eigenvalues.size() > std::size_t(tracked_roots))
      p.eigenvalues.resize(std::size_t(tracked_roots));
    for (const auto& s : p.eigenvalues) p.scale = std::max(p.scale, std::abs(s));
    p.lambda = parameter == FlutterParameter::lambda ? value : setting.lambda_of_mach(value);
    p.mach = parameter == FlutterParameter::mach ? value : setting.mach_of_lambda(value);
    if (on_value) on_value(++solved);
    return p;
  };
  // Unstable: a root with sigma above round-off (undamped roots below the coalescence are
  // imaginary up to ~1e-13 max |s|).
  const auto unstable = [](const FlutterPoint& p) {
    for (const auto& s : p.eigenvalues)
      if (s.real() > 1e-8 * p.scale) return true;
    return false;
  };
  for (int i = 0; i < points; ++i) sweep.points.push_back(evaluate(lo + (hi - lo) * i / (points - 1)));
  for (std::size_t i = 1; i < sweep.points.size(); ++i) {
    if (!unstable(sweep.points[i]) || unstable(sweep.points[i - 1])) continue;
    double a = sweep.points[i - 1].value, b = sweep.points[i].value;
    FlutterPoint upper = sweep.points[i];
    FlutterCritical c;
    while (b - a > relative_tolerance * std::abs(b) && c.bisections < 200) {
      const double mid = 0.5 * (a + b);
      FlutterPoint p = evaluate(mid);
      if (unstable(p)) {
        b = mid;
        upper = std::move(p);
      } else {
        a = mid;
      }
      ++c.bisections;
    }
    c.value = b;
    c.lambda = upper.lambda;
    c.mach = upper.mach;
    const auto crossing = std::max_element(upper.eigenvalues.begin(), upper.eigenvalues.end(),
                                           [](const auto& x, const auto& y) { return x.real() < y.real(); });
    c.frequency_hz = std::abs(crossing->imag()) / (2.0 * std::numbers::pi);
    sweep.critical = c;
    break;
  }
  return sweep;
}

double dense_eigenvalue_seconds(Eigen::Index n) {
  const Eigen::MatrixXd probe = Eigen::MatrixXd::Random(200, 200);
  const auto t0 = std::chrono::steady_clock::now();
  const Eigen::EigenSolver<Eigen::MatrixXd> es(probe, false);
  const double t200 = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return t200 * std::pow(double(n) / 200.0, 3);
}

double panel_length(const shell::ShellModel& model, const Vec3& direction) {
  const Vec3 d = direction.normalized();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Vec3& x : model.mesh().nodes) {
    lo = std::min(lo, x.dot(d));
    hi = std::max(hi, x.dot(d));
  }
  return hi - lo;
}

std::string to_string(FlutterParameter p) { return p == FlutterParameter::lambda ? "lambda" : "mach"; }

}  // namespace shellflow::coupling
