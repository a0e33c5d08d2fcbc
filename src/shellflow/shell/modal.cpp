#include "shellflow/shell/modal.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "shellflow/core/error.h"

namespace shellflow::shell {
namespace {

/// Throws SolverError naming a rigid-body motion that no support touches. Such a motion has
/// no strain energy, so K is singular, but the sparse LDLT does not say so reliably: its
/// pivots are round-off (~1e-16 of the transverse-normal stiffness E/h), rarely exactly zero,
/// and the iteration would return a meaningless "frequency" near zero. Per rigid motion r
/// (3 translations, 3 rotations about the centroid: Δx = t + ω × (X − c), ΔG = ω × G0) the
/// supports see its fixed part; the generalised eigenproblem Fᵀ F v = μ Rᵀ R v gives the
/// smallest fraction μ of a rigid motion's squared norm that lies on fixed dofs.
void check_rigid_motions_are_fixed(const ShellModel& model) {
  const Index nodes = model.num_nodes();
  const auto& X = model.mesh().nodes;
  Vec3 c = Vec3::Zero();
  for (const Vec3& x : X) c += x;
  c /= static_cast<double>(nodes);
  const double length = std::max(model.reference_length(), 1e-300);
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(model.num_dofs(), 6);
  for (Index n = 0; n < nodes; ++n) {
    const auto k = static_cast<std::size_t>(n);
    for (int i = 0; i < 3; ++i) {
      R(dofs_per_node * n + i, i) = 1.0;
      const Vec3 w = Vec3::Unit(i) / length;  // rotations scaled to unit displacement at `length`
      R.block<3, 1>(dofs_per_node * n, 3 + i) = w.cross(X[k] - c);
      R.block<3, 1>(dofs_per_node * n + 3, 3 + i) = w.cross(model.directors()[k]);
    }
  }
  Eigen::MatrixXd F = R;
  for (int j = 0; j < 6; ++j) {
    Eigen::VectorXd free = R.col(j);
    model.remove_fixed_part(free);
    F.col(j) -= free;
  }
  const Eigen::MatrixXd FF = F.transpose() * F;
  const Eigen::MatrixXd RR = R.transpose() * R;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> fraction(0.5 * (FF + FF.transpose()),
                                                                     0.5 * (RR + RR.transpose()));
  if (fraction.info() != Eigen::Success || fraction.eigenvalues()(0) > 1e-10) return;
  Eigen::VectorXd v = fraction.eigenvectors().col(0);
  Eigen::Index largest = 0;
  v.cwiseAbs().maxCoeff(&largest);
  if (v(largest) < 0.0) v = -v;  // the motion's sign is arbitrary: print its largest part positive
  const Vec3 t = v.head<3>(), w = v.tail<3>();
  const auto clean = [](double x) { return std::abs(x) < 1e-9 ? 0.0 : x; };  // no "-3e-21", no "-0"
  const auto vec = [&](const Vec3& a) {
    return fmt::format("[{:.3g}, {:.3g}, {:.3g}]", clean(a.x()), clean(a.y()), clean(a.z()));
  };
  throw SolverError(
      fmt::format("shell modal analysis: no support stops the rigid-body {} {} (the stiffness matrix is "
                  "singular); add or extend supports so that the shell cannot move freely",
                  w.norm() > t.norm() ? "rotation about an axis along" : "translation along",
                  vec((w.norm() > t.norm() ? w : t).normalized())));
}

}  // namespace

ModalResult natural_frequencies(const ShellModel& model, int count, const Eigen::VectorXd& u,
                                const ModalOptions& options) {
  const auto& fixed = model.constrained();
  SparseMatrix K = model.make_matrix();
  SparseMatrix M = model.make_matrix();
  Eigen::VectorXd f;
  model.assemble(u, f, &K);
  model.assemble_mass(M);
  check_rigid_motions_are_fixed(model);
  // Supports along non-axis directions (symmetry planes, rollers, hard simple support) flag
  // local components in constrained(): both matrices go to the node frames (Tᵀ A T, T
  // orthogonal, so M-normalisation is kept) and the modes come back with T.
  model.to_local(K);
  model.to_local(M);
  // Supports: identity in K, zero in M (their modes are pushed to infinity).
  for (int col = 0; col < K.outerSize(); ++col) {
    SparseMatrix::InnerIterator itM(M, col);
    for (SparseMatrix::InnerIterator it(K, col); it; ++it, ++itM) {
      if (!fixed[static_cast<std::size_t>(col)] && !fixed[static_cast<std::size_t>(it.row())]) continue;
      it.valueRef() = it.row() == col ? 1.0 : 0.0;
      itM.valueRef() = 0.0;
    }
  }
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt(K);
  if (ldlt.info() != Eigen::Success)
    throw SolverError("shell modal analysis: the stiffness matrix is singular; check the supports");

  const Eigen::Index n = K.rows();
  // The modes there are: one per free dof that carries mass (M's other rows are zero).
  Eigen::Index massful = 0;
  for (Eigen::Index i = 0; i < n; ++i) massful += M.coeff(i, i) > 0.0 ? 1 : 0;
  if (count > massful)
    throw SolverError(fmt::format(
        "shell modal analysis: {} modes asked for, but the supported shell has {} free degrees of freedom with "
        "mass, so {} modes at most: ask for fewer (shell.analysis.modes, flutter --modes) or refine the mesh",
        count, massful, massful));
  const int p = static_cast<int>(std::min<Eigen::Index>(count + options.extra_vectors, massful));
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> dist(-1.0, 1.0);
  Eigen::MatrixXd X(n, p);
  for (Eigen::Index i = 0; i < X.size(); ++i) X.data()[i] = dist(rng);

  ModalResult result;
  Eigen::VectorXd previous = Eigen::VectorXd::Constant(p, -1.0);
  for (int it = 1; it <= options.max_iterations; ++it) {
    const Eigen::MatrixXd Y = ldlt.solve(Eigen::MatrixXd(M * X));
    const Eigen::MatrixXd Kr = Y.transpose() * (K * Y);
    const Eigen::MatrixXd Mr = Y.transpose() * (M * Y);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ritz(0.5 * (Kr + Kr.transpose()),
                                                                   0.5 * (Mr + Mr.transpose()));
    if (ritz.info() != Eigen::Success) throw SolverError("shell modal analysis: Rayleigh–Ritz step failed");
    X = Y * ritz.eigenvectors();  // M-orthonormal
    const Eigen::VectorXd lambda = ritz.eigenvalues();
    const double change = ((lambda - previous).head(count).cwiseAbs().array() / lambda.head(count).array()).maxCoeff();
    previous = lambda;
    if (change < options.tolerance) {
      // A mechanism that is not a rigid motion (a hinge line) leaves K singular too: its
      // eigenvalue is round-off of either sign.
      if (!(lambda(0) > 0.0))
        throw SolverError(
            "shell modal analysis: the stiffness matrix is singular (a zero-energy "
            "mode); check the supports");
      result.iterations = it;
      // Each mode's sign fixed by its projection on a fixed generic vector: the Ritz solver's
      // sign follows round-off (a different thread count flipped a strip's second mode), and a
      // record in modal coordinates (an identification) must meet the same modes again.
      std::mt19937 sign_rng(2);
      std::uniform_real_distribution<double> weight(0.5, 1.5);
      Eigen::VectorXd probe(n);
      for (Eigen::Index i = 0; i < n; ++i) probe(i) = weight(sign_rng);
      for (int k = 0; k < count; ++k) {
        result.frequencies.push_back(std::sqrt(lambda(k)) / (2.0 * std::numbers::pi));
        Eigen::VectorXd phi = X.col(k);
        if (probe.dot(phi) < 0.0) phi = -phi;
        model.to_global(phi);
        result.modes.push_back(std::move(phi));
      }
      return result;
    }
  }
  throw SolverError(
      fmt::format("shell modal analysis: subspace iteration did not converge in {} iterations "
                  "to a relative eigenvalue change of {:.3g}; allow more iterations or a "
                  "larger tolerance",
                  options.max_iterations, options.tolerance));
}

}  // namespace shellflow::shell
