#include "shellflow/shell/newmark_solver.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "shellflow/core/error.h"

namespace shellflow::shell {

namespace {

SparseMatrix mass_of(const ShellModel& model) {
  SparseMatrix M = model.make_matrix();
  model.assemble_mass(M);
  return M;
}

}  // namespace

NodalMass::NodalMass(const SparseMatrix& M) {
  const Index n = M.rows() / dofs_per_node;
  std::vector<Eigen::Triplet<double, int>> xx, xG, Gx, GG;
  for (int col = 0; col < M.outerSize(); ++col) {
    const int b = col % dofs_per_node;
    if (b != 0 && b != 3) continue;
    for (SparseMatrix::InnerIterator it(M, col); it; ++it) {
      const int a = static_cast<int>(it.row() % dofs_per_node);
      const auto j = static_cast<int>(it.row() / dofs_per_node), k = col / dofs_per_node;
      if (a == 0 && b == 0) xx.emplace_back(j, k, it.value());
      if (a == 0 && b == 3) xG.emplace_back(j, k, it.value());
      if (a == 3 && b == 0) Gx.emplace_back(j, k, it.value());
      if (a == 3 && b == 3) GG.emplace_back(j, k, it.value());
    }
  }
  for (auto [matrix, entries] :
       {std::pair{&xx_, &xx}, std::pair{&xG_, &xG}, std::pair{&Gx_, &Gx}, std::pair{&GG_, &GG}}) {
    matrix->resize(n, n);
    matrix->setFromTriplets(entries->begin(), entries->end());
  }
}

Eigen::VectorXd NodalMass::operator*(const Eigen::VectorXd& v) const {
  using Part = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>, 0, Eigen::OuterStride<>>;
  const Index n = xx_.rows();
  const Part x(v.data(), n, 3, Eigen::OuterStride<>(dofs_per_node));
  const Part G(v.data() + 3, n, 3, Eigen::OuterStride<>(dofs_per_node));
  const Eigen::Matrix<double, Eigen::Dynamic, 3> px = xx_ * x + xG_ * G, pG = Gx_ * x + GG_ * G;
  Eigen::VectorXd out = Eigen::VectorXd::Zero(v.size());
  for (Index j = 0; j < n; ++j) {
    out.segment<3>(dofs_per_node * j) = px.row(j).transpose();
    out.segment<3>(dofs_per_node * j + 3) = pG.row(j).transpose();
  }
  return out;
}

NewmarkSolver::NewmarkSolver(const ShellModel& model, NewmarkOptions options, std::function<double(double)> load_factor)
    : model_(model),
      options_(options),
      load_factor_(std::move(load_factor)),
      u_(Eigen::VectorXd::Zero(model.num_dofs())),
      v_(u_),
      a_(u_),
      M_(mass_of(model)),
      K_(model.make_matrix()),
      nodal_mass_(M_),
      linear_solver_(model) {
  inertial_fixed_ = model_.constrained();
  for (Index n = 0; n < model_.num_nodes(); ++n) inertial_fixed_[static_cast<std::size_t>(dofs_per_node * n + 6)] = 1;
}

void NewmarkSolver::set_initial_state(const Eigen::VectorXd& u, const Eigen::VectorXd& v) {
  u_ = u;
  v_ = v;
  model_.apply_prescribed(time_, u_);
  // Supported components do not move (prescribed ones move at their prescribed rate), and
  // `a` has no velocity (§7).
  model_.remove_fixed_part(v_);
  model_.apply_prescribed_velocity(time_, v_);
  for (Index n = 0; n < model_.num_nodes(); ++n) v_(dofs_per_node * n + 6) = 0.0;
  Eigen::VectorXd f_ext = load_factor_at(time_) * model_.reference_load();
  model_.add_follower_loads(u_, load_factor_at(time_), time_, f_ext, nullptr);
  subtract_linear_load(u_, v_, f_ext);
  model_.assemble(u_, f_int_, nullptr);
  Eigen::VectorXd rhs = f_ext - f_int_ - options_.mass_damping * (nodal_mass_ * v_);
  SparseMatrix M = M_;
  ShellSystemSolver mass_solver(model_, inertial_fixed_);
  if (!mass_solver.factorize(M, true) || !mass_solver.solve(rhs))
    throw SolverError("shell dynamics: the mass matrix is singular on the position/director dofs");
  a_ = rhs;
}

void NewmarkSolver::set_linear_load(const SparseMatrix* stiffness, const SparseMatrix* damping) {
  const SparseMatrix& pattern = K_;
  for (const auto& [matrix, name] : {std::pair{stiffness, "stiffness"}, std::pair{damping, "damping"}}) {
    if (!matrix) continue;
    const bool same =
        matrix->rows() == pattern.rows() && matrix->cols() == pattern.cols() && matrix->isCompressed() &&
        matrix->nonZeros() == pattern.nonZeros() &&
        std::equal(pattern.outerIndexPtr(), pattern.outerIndexPtr() + pattern.cols() + 1, matrix->outerIndexPtr()) &&
        std::equal(pattern.innerIndexPtr(), pattern.innerIndexPtr() + pattern.nonZeros(), matrix->innerIndexPtr());
    if (!same)
      throw InputError(fmt::format(
          "shell dynamics: the linear load {} matrix must have the pattern of ShellModel::make_matrix ({}x{}, {} "
          "entries; got {}x{}, {} entries)",
          name, pattern.rows(), pattern.cols(), pattern.nonZeros(), matrix->rows(), matrix->cols(),
          matrix->nonZeros()));
  }
  linear_stiffness_ = stiffness;
  linear_damping_ = damping;
  matrix_factorized_ = false;
}

void NewmarkSolver::subtract_linear_load(const Eigen::VectorXd& y, const Eigen::VectorXd& v,
                                         Eigen::VectorXd& f_ext) const {
  if (linear_stiffness_) f_ext -= *linear_stiffness_ * y;
  if (linear_damping_) f_ext -= *linear_damping_ * v;
}

NewmarkState NewmarkSolver::state() const { return {u_, v_, a_, time_}; }

void NewmarkSolver::restore(const NewmarkState& state) {
  const Eigen::Index n = model_.num_dofs();
  if (state.u.size() != n || state.v.size() != n || state.a.size() != n)
    throw InputError(fmt::format("shell dynamics: restored state has {}, {}, {} entries, the model has {} dofs",
                                 state.u.size(), state.v.size(), state.a.size(), n));
  u_ = state.u;
  v_ = state.v;
  a_ = state.a;
  time_ = state.time;
  matrix_factorized_ = false;
  refresh_matrix_ = false;
}

void NewmarkSolver::rewind(const NewmarkState& state) {
  const bool factorized = matrix_factorized_, refresh = refresh_matrix_;
  restore(state);
  matrix_factorized_ = factorized;
  refresh_matrix_ = refresh;
}

void NewmarkSolver::save(ArchiveWriter& out) const {
  out.put(u_);
  out.put(v_);
  out.put(a_);
  out.put(time_);
  out.put(matrix_factorizations_);
  out.put(whole_matrix_);
  const bool kept = options_.newton.modified && matrix_factorized_;
  out.put(kept);
  if (!kept) return;
  out.put(kept_matrix_values_);
  out.put(factorized_mass_coefficient_);
  out.put(refresh_matrix_);
  out.put(last_residual_);
  out.put(symmetrised_);
  out.put(solves_since_factorization_);
}

void NewmarkSolver::restore(ArchiveReader& in) {
  NewmarkState s;
  s.u = in.get_eigen();
  s.v = in.get_eigen();
  s.a = in.get_eigen();
  s.time = in.get<double>();
  const auto n = static_cast<std::size_t>(model_.num_dofs());
  in.expect_size("the shell's displacement vector", std::size_t(s.u.size()), n);
  in.expect_size("the shell's velocity vector", std::size_t(s.v.size()), n);
  in.expect_size("the shell's acceleration vector", std::size_t(s.a.size()), n);
  restore(s);
  matrix_factorizations_ = in.get<int>();
  whole_matrix_ = in.get<bool>();
  if (!in.get<bool>()) return;
  std::vector<double> values = in.get_vector<double>();
  in.expect_size("the shell's iteration matrix", values.size(), std::size_t(K_.nonZeros()));
  factorized_mass_coefficient_ = in.get<double>();
  const bool refresh = in.get<bool>();
  last_residual_ = in.get<double>();
  symmetrised_ = in.get<bool>();
  solves_since_factorization_ = in.get<int>();
  std::copy(values.begin(), values.end(), K_.valuePtr());
  kept_matrix_values_ = std::move(values);
  matrix_factorized_ = linear_solver_.factorize(K_, symmetrised_ || (model_.symmetric_tangent() && !has_linear_load()));
  if (!matrix_factorized_) throw Error(in.what() + ": the shell's kept iteration matrix cannot be factorised");
  refresh_matrix_ = refresh;
}

Vec3 NewmarkSolver::linear_momentum() const {
  const Eigen::VectorXd Mv = nodal_mass_ * v_;
  Vec3 p = Vec3::Zero();
  for (Index n = 0; n < model_.num_nodes(); ++n) p += Mv.segment<3>(dofs_per_node * n);
  return p;
}

Vec3 NewmarkSolver::angular_momentum() const {
  const Eigen::VectorXd Mv = nodal_mass_ * v_;
  Vec3 l = Vec3::Zero();
  for (Index n = 0; n < model_.num_nodes(); ++n) {
    const Vec3 x = model_.mesh().nodes[static_cast<std::size_t>(n)] + node_position_increment(u_, n);
    const Vec3 G = model_.directors()[static_cast<std::size_t>(n)] + node_director_increment(u_, n);
    l += x.cross(Vec3(Mv.segment<3>(dofs_per_node * n))) + G.cross(Vec3(Mv.segment<3>(dofs_per_node * n + 3)));
  }
  return l;
}

// The Newton iterations both schemes share. g(u) = F_int(y) - F_ext(t, y) + inertia(u) with
// y = evaluation_state(u); inertia_forces(u) returns {the inertia and damping terms of g,
// the inertia force M ü for the force scale}; the iteration matrix is
// tangent_weight K(y) + mass_coefficient M.
template <class EvaluationState, class EvaluationVelocity, class InertiaForces>
int NewmarkSolver::iterate(Eigen::VectorXd& u, double load_factor, double time, double tangent_weight,
                           double mass_coefficient, double velocity_coefficient, EvaluationState&& evaluation_state,
                           EvaluationVelocity&& evaluation_velocity, InertiaForces&& inertia_forces) {
  for (int it = 1; it <= options_.newton.max_iterations; ++it) {
    const bool new_matrix = needs_new_matrix(mass_coefficient);
    const Eigen::VectorXd y = evaluation_state(u);
    if (!model_.assemble(y, f_int_, new_matrix ? &K_ : nullptr)) return -1;
    Eigen::VectorXd f_ext = load_factor * model_.reference_load();
    model_.add_follower_loads(y, load_factor, time, f_ext, new_matrix ? &K_ : nullptr);
    if (has_linear_load()) subtract_linear_load(y, evaluation_velocity(u), f_ext);
    const auto [inertia, inertia_force] = inertia_forces(u);
    const Eigen::VectorXd g = f_int_ - f_ext + inertia;
    if (new_matrix && !factorize_iteration_matrix(tangent_weight, mass_coefficient, velocity_coefficient)) return -1;
    const double force_scale =
        std::max({model_.free_norm(f_ext), model_.free_norm(f_int_), model_.free_norm(inertia_force)});
    record_residual(it, model_.free_norm(g));
    Eigen::VectorXd du = -g;
    if (!linear_solver_.solve(du)) return -1;
    ++solves_since_factorization_;
    u += du;
    if (!u.allFinite()) return -1;
    if (newton_converged(model_, options_.newton, du, g, force_scale)) return it;
  }
  return -1;
}

bool NewmarkSolver::needs_new_matrix(double mass_coefficient) const {
  return !options_.newton.modified || !matrix_factorized_ || refresh_matrix_ ||
         factorized_mass_coefficient_ != mass_coefficient;
}

bool NewmarkSolver::factorize_iteration_matrix(double tangent_weight, double mass_coefficient,
                                               double velocity_coefficient) {
  // H on the common pattern of K, M (and A, B).
  double* h = K_.valuePtr();
  const double* m = M_.valuePtr();
  for (Eigen::Index i = 0; i < K_.nonZeros(); ++i) h[i] = tangent_weight * h[i] + mass_coefficient * m[i];
  if (linear_stiffness_) {
    const double* A = linear_stiffness_->valuePtr();
    for (Eigen::Index i = 0; i < K_.nonZeros(); ++i) h[i] += tangent_weight * A[i];
  }
  if (linear_damping_) {
    const double* B = linear_damping_->valuePtr();
    for (Eigen::Index i = 0; i < K_.nonZeros(); ++i) h[i] += velocity_coefficient * B[i];
  }
  ++matrix_factorizations_;
  symmetrised_ = symmetrises_iteration_matrix();
  if (symmetrised_) symmetrise_iteration_matrix();
  // Factorising changes K_ in place (local frames, supports eliminated): keep H for a checkpoint.
  if (options_.newton.modified) kept_matrix_values_.assign(h, h + K_.nonZeros());
  matrix_factorized_ = linear_solver_.factorize(K_, symmetrised_ || (model_.symmetric_tangent() && !has_linear_load()));
  factorized_mass_coefficient_ = mass_coefficient;
  refresh_matrix_ = false;
  solves_since_factorization_ = 0;
  return matrix_factorized_;
}

// Modified Newton needs a matrix that contracts, not the exact tangent. In dynamics the mass
// term M/(beta dt^2) dominates H, and a follower pressure's load stiffness is small next to
// it: the symmetric part of H contracts as well, and its LDL^T costs a fraction of a sparse
// LU (5x on a 12 x 12 cubic plate). A linear load (set_linear_load: piston theory's A and B
// in the monolithic scheme) keeps the whole matrix: its skew part is large, and with it the
// first iteration of a linear problem is exact, whatever the amplitude. (With the symmetric
// part, a motion of 1e-12 m passes the absolute convergence tests with the first iterate's
// error: 7e-2 of the peak after 1 200 steps on the strip.)
bool NewmarkSolver::symmetrises_iteration_matrix() const {
  return options_.newton.modified && !whole_matrix_ && !has_linear_load() && !model_.symmetric_tangent();
}

void NewmarkSolver::symmetrise_iteration_matrix() {
  const auto nnz = static_cast<std::size_t>(K_.nonZeros());
  if (transpose_entry_.size() != nnz) {
    transpose_entry_.assign(nnz, -1);
    for (int col = 0; col < K_.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(K_, col); it; ++it) {
        const double* transposed = &K_.coeffRef(col, it.row());  // the pattern is symmetric (node pairs)
        transpose_entry_[static_cast<std::size_t>(&it.value() - K_.valuePtr())] =
            static_cast<int>(transposed - K_.valuePtr());
      }
  }
  double* h = K_.valuePtr();
  for (std::size_t k = 0; k < nnz; ++k) {
    const auto t = static_cast<std::size_t>(transpose_entry_[k]);
    if (t > k) h[k] = h[t] = 0.5 * (h[k] + h[t]);
  }
}

void NewmarkSolver::record_residual(int iteration, double residual_norm) {
  if (options_.newton.modified && iteration > 1 && residual_norm > options_.newton.refresh_ratio * last_residual_) {
    refresh_matrix_ = true;
    // A symmetric part that fails at its first solve will not do better when refreshed.
    if (symmetrised_ && solves_since_factorization_ == 1) whole_matrix_ = true;
  }
  last_residual_ = residual_norm;
}

int NewmarkSolver::try_step(double dt) {
  return options_.scheme == TimeScheme::midpoint ? try_midpoint_step(dt) : try_newmark_step(dt);
}

int NewmarkSolver::try_newmark_step(double dt) {
  const double beta = options_.beta, gamma = options_.gamma, cm = options_.mass_damping;
  const double t_next = time_ + dt;
  // Q_s and R_s of shell.md §7 in increments (the y0 terms cancel).
  const Eigen::VectorXd Q = u_ / (beta * dt * dt) + v_ / (beta * dt) + (0.5 / beta - 1.0) * a_;
  const Eigen::VectorXd R = v_ + (1.0 - gamma) * dt * a_;
  const double mass_coefficient = 1.0 / (beta * dt * dt) + cm * gamma / (beta * dt);
  const Eigen::VectorXd MQ = nodal_mass_ * Q;
  Eigen::VectorXd inertia_history = -MQ;
  if (cm != 0.0) inertia_history += cm * (nodal_mass_ * R) - cm * gamma * dt * MQ;
  const double lf = load_factor_at(t_next);

  Eigen::VectorXd u = u_;  // predictor y_{s+1}^(0) = y_s (papers' practice)
  model_.apply_prescribed(t_next, u);
  // Forces at u itself; H = K - K_load + (1/(beta dt²) + gamma c_m/(beta dt)) M.
  // Linear load: v_{n+1}(u) = R + gamma dt a_{n+1}(u) = R - gamma dt Q + gamma/(beta dt) u.
  const double velocity_coefficient = gamma / (beta * dt);
  const int iterations = iterate(
      u, lf, t_next, 1.0, mass_coefficient, velocity_coefficient, [](const Eigen::VectorXd& y) { return y; },
      [&](const Eigen::VectorXd& y) { return Eigen::VectorXd(R - gamma * dt * Q + velocity_coefficient * y); },
      [&](const Eigen::VectorXd& y) {
        const Eigen::VectorXd My = nodal_mass_ * y;
        return std::pair{Eigen::VectorXd(mass_coefficient * My + inertia_history),
                         Eigen::VectorXd(My / (beta * dt * dt) - MQ)};
      });
  if (iterations < 0) return -1;
  const Eigen::VectorXd a_next = u / (beta * dt * dt) - Q;
  v_ = R + gamma * dt * a_next;
  a_ = a_next;
  for (Index n = 0; n < model_.num_nodes(); ++n) v_(dofs_per_node * n + 6) = a_(dofs_per_node * n + 6) = 0.0;
  u_ = u;
  time_ = t_next;
  return iterations;
}

int NewmarkSolver::try_midpoint_step(double dt) {
  // Residual in the end state u = u_{n+1} (all rows, `a` included):
  //   g = F_int(u_mid) - F_ext(t_mid, u_mid) + (2/dt²) M (u - u_n - dt v_n) + c_m M (u - u_n)/dt,
  // i.e. (2/dt) × [M (v_{n+1} - v_n)/dt + C v_mid + F_int - F_ext], with u_mid = (u_n + u)/2.
  // The `a` rows carry no mass, so they say F_int,a(u_mid) = 0: `a` is in equilibrium with
  // x, G at the midpoint, where the forces act, and a_{n+1} = 2 a_mid - a_n follows the
  // straight path of the other dofs (exact for the linear relation a(x, G) of small strains).
  // That keeps the discrete energy balance T_{n+1} + U(u_{n+1}) - T_n - U(u_n) = midpoint
  // quadrature error of ∫F·du along the step, zero for a quadratic U.
  const double cm = options_.mass_damping;
  const double t_mid = time_ + 0.5 * dt;
  const double mass_coefficient = 2.0 / (dt * dt) + cm / dt;
  const Eigen::VectorXd Mv = nodal_mass_ * v_;
  const double lf = load_factor_at(t_mid);

  Eigen::VectorXd u = u_ + dt * v_;  // explicit predictor (v is zero on `a`)
  model_.apply_prescribed(time_ + dt, u);
  // Forces at u_mid = (u_n + u)/2; H = dg/du = (K - K_load)(u_mid) / 2 + (2/dt² + c_m/dt) M.
  // Linear load: y_mid = (u_n + u)/2, v_mid = (v_n + v_{n+1})/2 = (u - u_n)/dt, so the
  // iteration matrix gets A/2 + B/dt.
  const int iterations = iterate(
      u, lf, t_mid, 0.5, mass_coefficient, 1.0 / dt,
      [&](const Eigen::VectorXd& y) { return Eigen::VectorXd(0.5 * (u_ + y)); },
      [&](const Eigen::VectorXd& y) { return Eigen::VectorXd((y - u_) / dt); },
      [&](const Eigen::VectorXd& y) {
        const Eigen::VectorXd M_du = nodal_mass_ * (y - u_);
        const Eigen::VectorXd M_acceleration = (2.0 / (dt * dt)) * M_du - (2.0 / dt) * Mv;
        return std::pair{Eigen::VectorXd(M_acceleration + (cm / dt) * M_du), M_acceleration};
      });
  if (iterations < 0) return -1;
  Eigen::VectorXd v_next = (2.0 / dt) * (u - u_) - v_;
  for (Index n = 0; n < model_.num_nodes(); ++n) v_next(dofs_per_node * n + 6) = 0.0;
  a_ = (v_next - v_) / dt;
  v_ = std::move(v_next);
  u_ = u;
  time_ += dt;
  return iterations;
}

int NewmarkSolver::advance(double dt) {
  // Sub-steps of dt / 2^level; one failure halves the remaining sub-steps' size.
  const double t_end = time_ + dt;
  int level = 0, iterations = 0;
  bool retried_with_new_matrix = false;
  while (time_ < t_end - 1e-12 * dt) {
    const double h = std::min(dt / static_cast<double>(1 << level), t_end - time_);
    const bool stale_matrix = options_.newton.modified && matrix_factorized_;
    const int its = try_step(h);
    if (its < 0) {
      matrix_factorized_ = false;
      if (symmetrised_) whole_matrix_ = true;          // no step fails for want of the exact matrix
      if (stale_matrix && !retried_with_new_matrix) {  // modified Newton: retry with a fresh matrix
        retried_with_new_matrix = true;
        continue;
      }
      retried_with_new_matrix = false;
      if (++level > options_.newton.max_cutbacks)
        throw SolverError(fmt::format(
            "shell dynamics: Newton did not converge at t = {:.6g} s (step {:.3g} s halved {} times); reduce the "
            "time step or check loads and supports",
            time_ + h, dt, options_.newton.max_cutbacks));
      continue;
    }
    iterations += its;
  }
  time_ = t_end;
  return iterations;
}

}  // namespace shellflow::shell
