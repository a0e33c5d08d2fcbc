// The hooks of NewmarkSolver for the coupling (newmark_solver.h): the linear external force
// -(A y + B v) against mass damping (B = c M) and against the exact discrete frequency of a
// rigid translation (A = alpha M), with the iteration count that only the right iteration
// matrix gives; exact state save / restore, bit for bit, under full and modified Newton, and
// through a checkpoint archive into a new solver.
#include <gtest/gtest.h>

#include <memory>

#include "reference_strip.h"
#include "shellflow/core/error.h"
#include "shellflow/shell/newmark_solver.h"

namespace shellflow::shell {
namespace {

double relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).norm() / b.norm(); }

/// The reference strip under a follower pressure (load factor 1) and point pressures.
ShellModel loaded_strip() {
  ShellModel model = reference_strip();
  model.add_follower_pressure({"", 40.0});
  model.add_follower_pressure({"", 10.0, TimeFunction::step(1.0, 2.5e-4)});  // a cavity
  std::vector<double> p;
  for (const LoadPoint& lp : model.load_points()) p.push_back(30.0 * lp.position.x());
  model.set_point_pressure(p);
  return model;
}

Eigen::VectorXd strip_velocity(const ShellModel& model) {
  Eigen::VectorXd v = Eigen::VectorXd::Zero(model.num_dofs());
  for (Index n = 0; n < model.num_nodes(); ++n) v(7 * n + 1) = 0.05;
  return v;
}

TEST(LinearLoad, DampingMatrixCMEqualsMassDampingC) {
  const ShellModel model = loaded_strip();
  const double c = 40.0;
  for (TimeScheme scheme : {TimeScheme::newmark, TimeScheme::midpoint}) {
    NewmarkOptions damped;
    damped.scheme = scheme;
    damped.mass_damping = c;
    NewmarkOptions hooked;
    hooked.scheme = scheme;
    NewmarkSolver a(model, damped, [](double) { return 1.0; }), b(model, hooked, [](double) { return 1.0; });
    const SparseMatrix B = c * b.mass();
    b.set_linear_load(nullptr, &B);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
    a.set_initial_state(zero, strip_velocity(model));
    b.set_initial_state(zero, strip_velocity(model));
    EXPECT_LT(relative(b.acceleration(), a.acceleration()), 1e-12);
    int its_a = 0, its_b = 0;
    for (int s = 0; s < 5; ++s) {
      its_a += a.advance(1e-4);
      its_b += b.advance(1e-4);
    }
    EXPECT_EQ(its_a, its_b);  // the same iteration matrix
    EXPECT_LT(relative(b.displacement(), a.displacement()), 1e-12);
    EXPECT_LT(relative(b.velocity(), a.velocity()), 1e-12);
  }
}

/// u_n of the scalar trapezoidal rule for u'' = -alpha u.
std::vector<double> scalar_trapezoidal(double alpha, double u0, double v0, double dt, int steps) {
  const double beta = 0.25, gamma = 0.5;
  double u = u0, v = v0, a = -alpha * u0;
  std::vector<double> out{u};
  for (int s = 0; s < steps; ++s) {
    const double Q = u / (beta * dt * dt) + v / (beta * dt) + (0.5 / beta - 1.0) * a;
    const double u1 = Q / (1.0 / (beta * dt * dt) + alpha);
    const double a1 = u1 / (beta * dt * dt) - Q;
    v += dt * ((1.0 - gamma) * a + gamma * a1);
    u = u1;
    a = a1;
    out.push_back(u);
  }
  return out;
}

TEST(LinearLoad, StiffnessAlphaMGivesARigidTranslationTheFrequencySqrtAlpha) {
  // No supports: a rigid translation along the normal has no internal force, so with
  // A = alpha M it obeys u'' = -alpha u exactly; both schemes reduce to the trapezoidal rule
  // for this linear system. alpha = 4/dt^2 (omega dt = 2): a wrong iteration matrix (without
  // A) contracts the Newton error only by 1/2 per iteration and cannot converge in 2.
  ShellSection section;
  section.thickness = 1.35e-3;
  section.material = {77.28e9, 0.33, 2710.0};
  const ShellModel model(cubic_mesh("strip_20x1.geo"), section);
  const double dt = 1e-4, alpha = 4.0 / (dt * dt), u0 = 2e-6, v0 = 0.05;
  const auto expected = scalar_trapezoidal(alpha, u0, v0, dt, 6);
  for (TimeScheme scheme : {TimeScheme::newmark, TimeScheme::midpoint}) {
    NewmarkOptions options;
    options.scheme = scheme;
    NewmarkSolver solver(model, options);
    const SparseMatrix A = alpha * solver.mass();
    solver.set_linear_load(&A, nullptr);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(model.num_dofs()), v = u;
    for (Index n = 0; n < model.num_nodes(); ++n) {
      u(7 * n + 1) = u0;
      v(7 * n + 1) = v0;
    }
    solver.set_initial_state(u, v);
    for (int s = 1; s <= 6; ++s) {
      EXPECT_LE(solver.advance(dt), 2) << "step " << s;
      double worst = 0.0;
      for (Index n = 0; n < model.num_nodes(); ++n)
        worst = std::max(worst, std::abs(solver.displacement()(7 * n + 1) - expected[static_cast<std::size_t>(s)]));
      EXPECT_LT(worst, 1e-9 * u0) << "step " << s;
    }
  }
}

TEST(LinearLoad, MatricesMustHaveTheModelPattern) {
  const ShellModel model = reference_strip();
  NewmarkSolver solver(model);
  SparseMatrix wrong(model.num_dofs(), model.num_dofs());
  wrong.insert(0, 0) = 1.0;
  wrong.makeCompressed();
  EXPECT_THROW(solver.set_linear_load(&wrong, nullptr), InputError);
  EXPECT_THROW(solver.set_linear_load(nullptr, &wrong), InputError);
  const SparseMatrix right = model.make_matrix();
  EXPECT_NO_THROW(solver.set_linear_load(&right, &right));
}

bool bitwise_equal(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  if (a.size() != b.size()) return false;
  for (Eigen::Index i = 0; i < a.size(); ++i)
    if (!(a(i) == b(i))) return false;
  return true;
}

void expect_same_bits(const NewmarkState& a, const NewmarkState& b) {
  EXPECT_TRUE(bitwise_equal(a.u, b.u));
  EXPECT_TRUE(bitwise_equal(a.v, b.v));
  EXPECT_TRUE(bitwise_equal(a.a, b.a));
  EXPECT_EQ(a.time, b.time);
}

TEST(NewmarkState, RestoreThenStepRepeatsTheStepsBitForBit) {
  const ShellModel model = loaded_strip();
  const double dt = 1e-4;
  for (TimeScheme scheme : {TimeScheme::newmark, TimeScheme::midpoint})
    for (bool modified : {false, true}) {
      SCOPED_TRACE(::testing::Message() << "midpoint " << (scheme == TimeScheme::midpoint) << " modified " << modified);
      NewmarkOptions options;
      options.scheme = scheme;
      options.newton.modified = modified;
      NewmarkSolver solver(model, options, [](double) { return 1.0; });
      solver.set_initial_state(Eigen::VectorXd::Zero(model.num_dofs()), strip_velocity(model));
      for (int s = 0; s < 3; ++s) solver.advance(dt);
      const NewmarkState saved = solver.state();
      // Modified Newton: a kept matrix is part of the path, and restore marks it stale, so
      // the reference path starts from a restore too.
      if (modified) solver.restore(saved);
      for (int s = 0; s < 2; ++s) solver.advance(dt);
      const NewmarkState reference = solver.state();
      EXPECT_GT(relative(reference.u, saved.u), 1e-3);
      solver.restore(saved);
      expect_same_bits(solver.state(), saved);
      for (int s = 0; s < 2; ++s) solver.advance(dt);
      expect_same_bits(solver.state(), reference);
      if (!modified) {  // = an uninterrupted run
        NewmarkSolver straight(model, options, [](double) { return 1.0; });
        straight.set_initial_state(Eigen::VectorXd::Zero(model.num_dofs()), strip_velocity(model));
        for (int s = 0; s < 5; ++s) straight.advance(dt);
        expect_same_bits(straight.state(), reference);
      }
    }
}

// A checkpoint (save into an archive, restore into a new solver) continues an uninterrupted
// run bit for bit, also under modified Newton, where the kept iteration matrix is part of
// the path: a restore of the state alone (a fresh matrix) leaves the path.
TEST(NewmarkCheckpoint, ANewSolverRestoredFromTheArchiveContinuesTheRunBitForBit) {
  const ShellModel model = loaded_strip();
  const double dt = 1e-4;
  for (TimeScheme scheme : {TimeScheme::newmark, TimeScheme::midpoint})
    for (bool modified : {false, true}) {
      SCOPED_TRACE(::testing::Message() << "midpoint " << (scheme == TimeScheme::midpoint) << " modified " << modified);
      NewmarkOptions options;
      options.scheme = scheme;
      options.newton.modified = modified;
      const auto make = [&] {
        auto solver = std::make_unique<NewmarkSolver>(model, options, [](double) { return 1.0; });
        solver->set_initial_state(Eigen::VectorXd::Zero(model.num_dofs()), strip_velocity(model));
        return solver;
      };
      auto straight = make();
      for (int s = 0; s < 6; ++s) straight->advance(dt);
      bool kept_matrix_matters = false;
      for (int split = 1; split < 6; ++split) {
        SCOPED_TRACE(::testing::Message() << "checkpoint after step " << split);
        auto first = make();
        for (int s = 0; s < split; ++s) first->advance(dt);
        ArchiveWriter out;
        first->save(out);
        const NewmarkState at_checkpoint = first->state();
        first.reset();

        auto second = make();
        ArchiveReader in(out.bytes(), "test checkpoint");
        second->restore(in);
        EXPECT_EQ(in.remaining(), 0u);
        expect_same_bits(second->state(), at_checkpoint);
        for (int s = split; s < 6; ++s) second->advance(dt);
        expect_same_bits(second->state(), straight->state());
        EXPECT_EQ(second->matrix_factorizations(), straight->matrix_factorizations());

        auto state_only = make();
        state_only->restore(at_checkpoint);
        for (int s = split; s < 6; ++s) state_only->advance(dt);
        kept_matrix_matters = kept_matrix_matters || state_only->state().u != straight->state().u;
      }
      // Without the kept matrix a restart leaves the path for some checkpoint step.
      EXPECT_EQ(kept_matrix_matters, modified);
    }
}

TEST(NewmarkCheckpoint, AnArchiveOfAnotherModelIsRefused) {
  const ShellModel model = loaded_strip();
  NewmarkSolver solver(model);
  ArchiveWriter out;
  out.put(Eigen::VectorXd(Eigen::VectorXd::Zero(7)));
  ArchiveReader in(out.bytes(), "other.ckpt");
  try {
    solver.restore(in);
    FAIL() << "restored a checkpoint of another model";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("other.ckpt"), std::string::npos) << e.what();
  }
}

TEST(NewmarkState, RestoreTakesTheStateAsGiven) {
  const ShellModel model = reference_strip();
  NewmarkSolver solver(model);
  NewmarkState s{Eigen::VectorXd::Random(model.num_dofs()), Eigen::VectorXd::Random(model.num_dofs()),
                 Eigen::VectorXd::Random(model.num_dofs()), 0.125};
  solver.restore(s);  // no acceleration solve, no support projection
  expect_same_bits(solver.state(), s);
  s.a.resize(3);
  EXPECT_THROW(solver.restore(s), InputError);
}

// The coupling iterations repeat a step from its start (NewmarkSolver::rewind): under
// modified Newton the kept matrix stays and is not factorised again, and the repeated step
// is the step made the first time, bit for bit.
TEST(NewmarkRewind, RepeatingAStepKeepsTheFactorisedMatrixAndGivesTheSameStep) {
  const ShellModel model = loaded_strip();
  const double dt = 1e-4;
  NewmarkOptions options;
  options.newton.modified = true;
  NewmarkSolver solver(model, options, [](double) { return 1.0; });
  solver.set_initial_state(Eigen::VectorXd::Zero(model.num_dofs()), strip_velocity(model));
  for (int s = 0; s < 3; ++s) solver.advance(dt);
  const NewmarkState start = solver.state();
  solver.advance(dt);
  const NewmarkState once = solver.state();
  const int factorizations = solver.matrix_factorizations();
  for (int k = 0; k < 5; ++k) {
    solver.rewind(start);
    solver.advance(dt);
    expect_same_bits(solver.state(), once);
  }
  EXPECT_EQ(solver.matrix_factorizations(), factorizations);
  // restore() instead marks the matrix stale: the next step factorises again.
  solver.restore(start);
  solver.advance(dt);
  EXPECT_EQ(solver.matrix_factorizations(), factorizations + 1);
}

}  // namespace
}  // namespace shellflow::shell
