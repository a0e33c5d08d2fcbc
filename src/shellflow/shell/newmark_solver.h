#pragma once
// Dynamics in the positional form of shell.md §7, written in the increments u = y - y0, with
// Newton in every step (§8), mass-proportional damping C = c_m M and step halving on
// failure. Two one-step schemes: Newmark (beta = 1/4, gamma = 1/2 by default) and the
// implicit midpoint rule, which also conserves angular momentum (see TimeScheme).
#include <functional>

#include "shellflow/core/archive.h"
#include "shellflow/shell/static_solver.h"

namespace shellflow::shell {

enum class TimeScheme {
  /// Newmark with `beta`, `gamma` (trapezoidal rule at 1/4, 1/2): conserves linear momentum
  /// and, in the linear range, energy; angular momentum drifts as O(dt^2).
  newmark,
  /// Implicit midpoint rule: (y1 - y0)/dt = (v0 + v1)/2 and
  /// M (v1 - v0)/dt = F_ext(t_mid, y_mid) - F_int(y_mid) - C v_mid with y_mid = (y0 + y1)/2.
  /// Conserves linear and angular momentum exactly (constant M with isotropic 3x3 blocks,
  /// objective F_int) and energy for quadratic energies (spec §7). Second order, no
  /// numerical damping; ignores `beta`, `gamma`.
  midpoint,
};

/// The consistent mass in node-pair form. Every 3x3 block of M is a multiple of the
/// identity (shell.md §6: M_jk = ∫ρ φ_j φ_k (1, ξ3 h/2, (ξ3 h/2)²) I) and the `a` rows are
/// empty, so M v needs 4 scalars per node pair (x–x, x–G, G–x, G–G) instead of 49 entries:
/// the product reads about 10× less memory than the sparse one (it runs in every iteration).
class NodalMass {
 public:
  /// M as made by ShellModel::assemble_mass.
  explicit NodalMass(const SparseMatrix& M);
  Eigen::VectorXd operator*(const Eigen::VectorXd& v) const;

 private:
  SparseMatrix xx_, xG_, Gx_, GG_;  ///< num_nodes x num_nodes
};

struct NewmarkOptions {
  TimeScheme scheme = TimeScheme::newmark;
  double beta = 0.25;
  double gamma = 0.5;
  double mass_damping = 0.0;  ///< c_m in C = c_m M (1/s)
  /// Modified Newton renews its matrix only when an iteration contracts the residual by less
  /// than 0.9 (statics: 0.5). In dynamics the mass term keeps a kept matrix close, and an
  /// iteration (an internal-force assembly and a solve) costs a twentieth of a factorisation
  /// on a 12 x 12 cubic plate: 0.9 takes 22 s of shell time where 0.5 takes 40 s for the
  /// clamped square's 0.06 s of piston-theory flutter, with the same states to 1e-9.
  NewtonOptions newton{.refresh_ratio = 0.9};
};

/// The whole state of a NewmarkSolver (NewmarkSolver::state / restore).
struct NewmarkState {
  Eigen::VectorXd u, v, a;
  double time = 0.0;
};

class NewmarkSolver {
 public:
  /// `load_factor(t)` multiplies the model's dead loads, edge couples and follower pressures
  /// without history; default 0. Follower pressures with a history and the model's point
  /// loads are not scaled by it. The solver reads the model's loads at every Newton
  /// iteration, so point loads set on the model between steps act in the next step.
  NewmarkSolver(const ShellModel& model, NewmarkOptions options = {}, std::function<double(double)> load_factor = {});

  /// Sets the initial state (u, v at the current time; u = 0 at rest) and computes the
  /// consistent acceleration from M a = F_ext - F_int - C v on the x and G rows. The `a`
  /// entries of u should be in equilibrium with its x and G (true at rest, for a mode or a
  /// static solution): the midpoint scheme carries them as given. Supported components
  /// get zero velocity; those with a prescribed motion take its position and rate at the
  /// current time (their initial acceleration is taken as zero), and every step moves them
  /// to their prescribed position at its end time.
  void set_initial_state(const Eigen::VectorXd& u, const Eigen::VectorXd& v);
  /// Advances by dt (sub-stepping by halves on failure, up to newton.max_cutbacks levels).
  /// Returns the Newton iterations used. Throws SolverError naming the time on failure.
  int advance(double dt);

  /// A linear external force −(A y + B ẏ) (e.g. a linearised aerodynamic model), evaluated
  /// at the scheme's state in every Newton iteration (Newmark: y = u_{n+1} and
  /// ẏ = v_{n+1}(u_{n+1}); midpoint: y = (u_n + u_{n+1})/2, ẏ = (u_{n+1} − u_n)/dt) and in
  /// set_initial_state, with its derivative in the iteration matrix: A · tangent_weight +
  /// B · velocity coefficient (Newmark γ/(β dt), midpoint 1/dt). y, ẏ are the increments
  /// and rates in global components. Either may be null (both null: removed). Both must
  /// have exactly the pattern of ShellModel::make_matrix (InputError otherwise) and outlive
  /// the solver or the next call; their values are read at every iteration. The iteration
  /// matrix is then factorised as non-symmetric. Call again after changing their values
  /// under modified Newton (it marks a kept matrix stale).
  void set_linear_load(const SparseMatrix* stiffness, const SparseMatrix* damping);

  /// The current state (u, v, a, time), exact.
  NewmarkState state() const;
  /// Sets the state exactly as given (no re-equilibration: no acceleration solve, no
  /// projection of the supports) and marks a kept modified-Newton iteration matrix stale.
  /// Throws InputError for vectors of the wrong size.
  void restore(const NewmarkState& state);
  /// Puts the solver back to `state` to repeat the same step (coupling iterations): like
  /// restore(), but a kept modified-Newton iteration matrix stays valid (the same step size
  /// and model, a state near the one it was made for), so no refactorisation follows.
  void rewind(const NewmarkState& state);

  /// Checkpoint (core/archive.h): the state and, under modified Newton, the kept iteration
  /// matrix (its values before the supports were eliminated, its mass coefficient and
  /// whether a refresh is due), so that the steps after restore() use the same matrix as the
  /// uninterrupted run and repeat it bit for bit. restore() factorises the kept matrix again.
  /// Throws Error for a checkpoint of another model (sizes).
  void save(ArchiveWriter& out) const;
  void restore(ArchiveReader& in);

  double time() const { return time_; }
  const Eigen::VectorXd& displacement() const { return u_; }
  const Eigen::VectorXd& velocity() const { return v_; }
  /// Newmark: the acceleration at time(); midpoint: the mean acceleration (v1 - v0)/dt of
  /// the last step (the value at its midpoint; second-order accurate there).
  const Eigen::VectorXd& acceleration() const { return a_; }
  double kinetic_energy() const { return 0.5 * v_.dot(nodal_mass_ * v_); }
  double strain_energy() const { return model_.strain_energy(u_); }
  /// Linear momentum ∫ρ0 v dV0 (shell.md §6 kinematics): with Σφ_k = 1 it is the sum of
  /// M v over the x rows of every node.
  Vec3 linear_momentum() const;
  /// Angular momentum about the origin ∫ρ0 x × v dV0 with x = x̂ + (ĥ/2) ξ3 ĝ (the map of
  /// the kinetic energy, §6): Σ_j x_j × (M v)_xj + G_j × (M v)_Gj, because every block of M
  /// is a multiple of the identity.
  Vec3 angular_momentum() const;
  const SparseMatrix& mass() const { return M_; }
  /// Factorisations of the iteration matrix so far (one per Newton iteration unless
  /// NewtonOptions::modified).
  int matrix_factorizations() const { return matrix_factorizations_; }
  const NewmarkOptions& options() const { return options_; }

 private:
  /// One step of size dt; -1 (state unchanged) when Newton fails.
  int try_step(double dt);
  int try_newmark_step(double dt);
  int try_midpoint_step(double dt);
  double load_factor_at(double t) const { return load_factor_ ? load_factor_(t) : 0.0; }
  /// Newton on the end state u of a step (the loop both schemes share); the iterations or -1.
  template <class EvaluationState, class EvaluationVelocity, class InertiaForces>
  int iterate(Eigen::VectorXd& u, double load_factor, double time, double tangent_weight, double mass_coefficient,
              double velocity_coefficient, EvaluationState&& evaluation_state, EvaluationVelocity&& evaluation_velocity,
              InertiaForces&& inertia_forces);
  /// Whether this iteration assembles and factorises the iteration matrix
  /// H = tangent_weight K + mass_coefficient M (always, unless NewtonOptions::modified).
  bool needs_new_matrix(double mass_coefficient) const;
  /// H from the K_ just assembled (+ tangent_weight A + velocity_coefficient B), factorised;
  /// false when singular.
  bool factorize_iteration_matrix(double tangent_weight, double mass_coefficient, double velocity_coefficient);
  bool has_linear_load() const { return linear_stiffness_ || linear_damping_; }
  /// Subtracts A y + B v from f_ext.
  void subtract_linear_load(const Eigen::VectorXd& y, const Eigen::VectorXd& v, Eigen::VectorXd& f_ext) const;
  /// Records the residual norm of an iteration (modified Newton: a poor contraction asks for
  /// a new matrix at the next iteration; a fresh symmetric part that contracts poorly makes
  /// every later matrix the whole one).
  void record_residual(int iteration, double residual_norm);
  /// Whether the next factorisation takes the symmetric part of a non-symmetric H (modified
  /// Newton only; shell.md, "Assembly and linear solver").
  bool symmetrises_iteration_matrix() const;
  /// H <- (H + H^T)/2 in place on K_'s (structurally symmetric) pattern.
  void symmetrise_iteration_matrix();

  const ShellModel& model_;
  NewmarkOptions options_;
  std::function<double(double)> load_factor_;
  double time_ = 0.0;
  Eigen::VectorXd u_, v_, a_;
  SparseMatrix M_, K_;
  NodalMass nodal_mass_;  ///< M_ for products
  Eigen::VectorXd f_int_;
  ShellSystemSolver linear_solver_;
  // Modified Newton state: the factorised H and the mass coefficient it was made with.
  bool matrix_factorized_ = false;
  bool refresh_matrix_ = false;
  double factorized_mass_coefficient_ = 0.0;
  double last_residual_ = 0.0;
  int matrix_factorizations_ = 0;
  bool symmetrised_ = false;   ///< the kept factorisation is of H's symmetric part
  bool whole_matrix_ = false;  ///< the symmetric part failed to contract: factorise H itself
  int solves_since_factorization_ = 0;
  std::vector<int> transpose_entry_;                ///< K_'s entry (j, i) for its entry (i, j)
  std::vector<double> kept_matrix_values_;          ///< modified Newton: H before its factorisation (checkpoints)
  std::vector<char> inertial_fixed_;                ///< constrained dofs plus every `a` (no inertia)
  const SparseMatrix* linear_stiffness_ = nullptr;  ///< A of set_linear_load
  const SparseMatrix* linear_damping_ = nullptr;    ///< B of set_linear_load
};

}  // namespace shellflow::shell
