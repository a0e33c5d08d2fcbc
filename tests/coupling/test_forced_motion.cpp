// The forced-motion identification path (coupling/forced_motion.h) driven by piston theory,
// whose GAF is known in closed form: the record fitted by one tap of [q; q'] returns piston
// theory's modal matrices to round-off, and the identified model's discrete flutter analysis
// returns the piston analysis's boundary.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "flutter_strip.h"
#include "shellflow/core/error.h"
#include "shellflow/coupling/aerodynamics.h"
#include "shellflow/coupling/discrete_flutter.h"
#include "shellflow/coupling/forced_motion.h"
#include "shellflow/coupling/gaf_identification.h"
#include "shellflow/coupling/linear_flutter.h"
#include "shellflow/coupling/modal_aerodynamics.h"

namespace shellflow::coupling {
namespace {

using namespace test_strip;

constexpr int kModes = 6;
constexpr double pi = std::numbers::pi;

/// The strip's forced-motion record under piston theory at step dt.
ForcedMotionRecord piston_record(const shell::ShellModel& model, const LinearFlutterSystem& sys, double dt) {
  PistonLoads loads(model, piston_flow());
  ShellStepMotion motion(model, 1e-6);
  ForcedModalMotion forced(model, sys.basis(), 1.5e-3, 5e-4, 1e-6, dt, loads, motion);
  const long steps = forced.total_steps();
  EXPECT_EQ(steps, std::lround(2 * kModes * 2e-3 / dt));
  while (forced.steps() < steps) forced.step();
  return forced.record();
}

/// Piston theory whose damping factor c = (M^2 - 2) / (M^2 - 1) stays at a given Mach number.
class FrozenDamping final : public ModalAerodynamics {
 public:
  FrozenDamping(const PistonAerodynamics& piston, double mach)
      : piston_(piston), c_((mach * mach - 2.0) / (mach * mach - 1.0)) {}
  AeroStateSpace at(const FlowCondition& flow) const override {
    const double beta = std::sqrt(flow.mach * flow.mach - 1.0);
    return piston_.at_coefficients(flow.dynamic_pressure_over_beta, flow.density * flow.speed * c_ / beta);
  }
  std::unique_ptr<ModalAerodynamics> truncated(int) const override { return nullptr; }
  std::string name() const override { return "piston theory, frozen damping"; }

 private:
  const PistonAerodynamics& piston_;
  double c_;
};

/// Piston theory whose damping factor c = (M^2 - 2) / (M^2 - 1) is interpolated linearly in
/// Mach between M1 and M2 (and frozen at the nearer one outside).
class InterpolatedDamping final : public ModalAerodynamics {
 public:
  InterpolatedDamping(const PistonAerodynamics& piston, double m1, double m2) : piston_(piston), m1_(m1), m2_(m2) {}
  AeroStateSpace at(const FlowCondition& flow) const override {
    const auto c = [](double m) { return (m * m - 2.0) / (m * m - 1.0); };
    const double w = std::clamp((m2_ - flow.mach) / (m2_ - m1_), 0.0, 1.0);
    const double beta = std::sqrt(flow.mach * flow.mach - 1.0);
    return piston_.at_coefficients(flow.dynamic_pressure_over_beta,
                                   flow.density * flow.speed * (w * c(m1_) + (1.0 - w) * c(m2_)) / beta);
  }
  std::unique_ptr<ModalAerodynamics> truncated(int) const override { return nullptr; }
  std::string name() const override { return "piston theory, interpolated damping"; }

 private:
  const PistonAerodynamics& piston_;
  double m1_, m2_;
};

FlowCondition case_flow() { return setting(true).flow(FlutterParameter::mach, 2.3); }

TEST(ForcedMotion, IdentifyingPistonTheoryReturnsItsModalMatrices) {
  const shell::ShellModel model = strip(20, Edges::clamped);
  const LinearFlutterSystem sys(model, kModes);
  const double dt = 1e-4;
  const ForcedMotionRecord record = piston_record(model, sys, dt);
  const FirFit fit = fit_fir(record.input_matrix(), record.force_matrix(), dt, {1, 0.0});
  const AeroStateSpace exact = PistonAerodynamics(sys, piston(model)).at(case_flow());
  Eigen::MatrixXd expected(kModes, 2 * kModes);
  expected << exact.D0, exact.D1;
  const Eigen::MatrixXd& H0 = fit.model.taps[0];
  std::printf("fit residual %.3e; |H0 - [D0 D1]| / |[D0 D1]| = %.3e\n", fit.residual,
              (H0 - expected).norm() / expected.norm());
  EXPECT_LT(fit.residual, 1e-12);
  EXPECT_LT((H0 - expected).norm(), 1e-10 * expected.norm());
  // The forces are the flow's at the motion's own time stamps: the stiffness part alone
  // (D0 q_n) explains the record only when nothing shifts the loads against the motion.
  EXPECT_LT((H0.leftCols(kModes) - exact.D0).norm(), 1e-10 * exact.D0.norm());
}

TEST(ForcedMotion, RestoreThenStepEqualsStep) {
  // A checkpoint in the middle of the pulses: the record and the window come back, and the
  // steps after it give the same samples, bit for bit.
  const shell::ShellModel model = strip(8, Edges::clamped);
  const LinearFlutterSystem sys(model, 3);
  PistonLoads loads(model, piston_flow());
  ShellStepMotion motion(model, 1e-6);
  ForcedModalMotion forced(model, sys.basis(), 1e-3, 5e-4, 1e-6, 1e-4, loads, motion);
  for (int n = 0; n < 23; ++n) forced.step();
  ArchiveWriter out;
  forced.save(out);
  for (int n = 0; n < 17; ++n) forced.step();
  PistonLoads loads2(model, piston_flow());
  ShellStepMotion motion2(model, 1e-6);
  ForcedModalMotion again(model, sys.basis(), 1e-3, 5e-4, 1e-6, 1e-4, loads2, motion2);
  ArchiveReader in(out.bytes(), "test");
  again.restore(in);
  EXPECT_EQ(again.steps(), 23);
  for (int n = 0; n < 17; ++n) again.step();
  ASSERT_EQ(again.record().forces.size(), forced.record().forces.size());
  for (std::size_t n = 0; n < forced.record().forces.size(); ++n) {
    EXPECT_EQ(again.record().time[n], forced.record().time[n]);
    EXPECT_TRUE((again.record().inputs[n].array() == forced.record().inputs[n].array()).all()) << n;
    EXPECT_TRUE((again.record().forces[n].array() == forced.record().forces[n].array()).all()) << n;
  }
  // A checkpoint of another run length is refused.
  ForcedModalMotion shorter(model, sys.basis(), 1e-4, 0.0, 1e-6, 1e-4, loads2, motion2);
  ArchiveReader in2(out.bytes(), "test");
  EXPECT_THROW(shorter.restore(in2), InputError);
}

TEST(ForcedMotion, TheIdentifiedModelReturnsThePistonAnalysis) {
  // Newmark's average acceleration with the forces of both ends is the trapezoidal rule, whose
  // map z = (1 + dt A / 2) / (1 - dt A / 2) takes Re s = 0 onto |z| = 1: the identified
  // model's boundary is the continuous piston analysis's exactly (lambda_cr, and so M_cr), and
  // its frequency is the continuous one warped, f_d = atan(pi f dt) / (pi dt), at the
  // model's step there.
  const shell::ShellModel model = strip(20, Edges::clamped);
  const LinearFlutterSystem sys(model, kModes);
  const FlutterSetting s = setting(true);
  const PistonAerodynamics piston_aero(sys, piston(model));
  const auto continuous = sweep_flutter(sys, piston_aero, s, FlutterParameter::lambda, 0.0, 1500.0, 16);
  ASSERT_TRUE(continuous.critical);
  for (const double dt : {1e-4, 5e-5}) {
    const ForcedMotionRecord record = piston_record(model, sys, dt);
    const FirFit fit = fit_fir(record.input_matrix(), record.force_matrix(), dt, {1, 0.0});
    const IdentifiedAerodynamics identified(fit.model.state_space(), case_flow(), DiscreteCoupling::simultaneous);
    const auto id = sweep_flutter(sys, identified, s, FlutterParameter::lambda, 0.0, 1500.0, 16);
    ASSERT_TRUE(id.critical);
    // A lambda sweep at fixed Mach changes the speed: the model's step is dt U0 / U there.
    const double f = continuous.critical->frequency_hz;
    const double step = dt * case_flow().speed / s.flow(FlutterParameter::lambda, id.critical->lambda).speed;
    const double warped = std::atan(pi * f * step) / (pi * step);
    std::printf(
        "dt %.0e: lambda_cr identified %.10g, piston analysis %.10g; %.8g Hz, warped %.8g Hz, continuous %.8g Hz\n", dt,
        id.critical->lambda, continuous.critical->lambda, id.critical->frequency_hz, warped, f);
    EXPECT_NEAR(id.critical->lambda, continuous.critical->lambda, 1e-8 * continuous.critical->lambda);
    EXPECT_NEAR(id.critical->frequency_hz, warped, 1e-6 * f);
    // M_cr at the case's density and pressure from the lambda sweep: the same conversion.
    EXPECT_NEAR(id.critical->mach, continuous.critical->mach, 1e-6);
    // A Mach sweep scales the model as one of reduced time t U / a with forces ~ rho U^2 / beta:
    // piston theory so scaled keeps its damping factor c = (M^2 - 2) / (M^2 - 1) at the
    // identification's Mach 2.3. Its boundary is that of piston theory with c frozen.
    const auto mach = sweep_flutter(sys, identified, s, FlutterParameter::mach, 1.5, 3.0, 16);
    const auto frozen = sweep_flutter(sys, FrozenDamping(piston_aero, 2.3), s, FlutterParameter::mach, 1.5, 3.0, 16);
    const auto mach_piston = sweep_flutter(sys, piston_aero, s, FlutterParameter::mach, 1.5, 3.0, 16);
    ASSERT_TRUE(mach.critical && frozen.critical && mach_piston.critical);
    std::printf("  Mach sweep: M_cr identified at 2.3 %.10g, piston with c(2.3) %.10g, piston %.10g\n",
                mach.critical->mach, frozen.critical->mach, mach_piston.critical->mach);
    EXPECT_NEAR(mach.critical->mach, frozen.critical->mach, 1e-6);
  }
}

TEST(ForcedMotion, LoadsLateByAFractionOfAStepMoveTheBoundary) {
  // The alignment the identification rests on, made visible: the record's forces taken
  // delta = 5 us (a twentieth of the step) after the motion's time stamps, f(t_n - delta)
  // filed at t_n, as a driver that read the loads of the step's start would. The delay is a
  // negative aerodynamic damping -delta D0 q': lambda_cr and M_cr fall by orders of magnitude
  // more than the 1e-8 (lambda) and 1e-6 (M) to which the aligned path meets the piston
  // analysis (TheIdentifiedModelReturnsThePistonAnalysis), so that test fails on any such
  // misalignment. On the Euler strip the same 5 us moves M_cr by about -0.007
  // (../design/identified_aero.md).
  const shell::ShellModel model = strip(20, Edges::clamped);
  const LinearFlutterSystem sys(model, kModes);
  const FlutterSetting s = setting(true);
  const double dt = 1e-4, delta = 5e-6;
  const ForcedMotionRecord record = piston_record(model, sys, dt);
  const Eigen::MatrixXd f = record.force_matrix();
  Eigen::MatrixXd late = f;  // linear in time between the samples: exact to O(dt^2) on the pulses
  for (Eigen::Index n = 1; n < f.rows(); ++n) late.row(n) = f.row(n) - (delta / dt) * (f.row(n) - f.row(n - 1));
  const auto boundary = [&](const Eigen::MatrixXd& forces) {
    const FirFit fit = fit_fir(record.input_matrix(), forces, dt, {2, 0.0});
    const IdentifiedAerodynamics id(fit.model.state_space(), case_flow(), DiscreteCoupling::simultaneous);
    const auto sweep = sweep_flutter(sys, id, s, FlutterParameter::lambda, 0.0, 1500.0, 16);
    EXPECT_TRUE(sweep.critical);
    return sweep.critical ? *sweep.critical : FlutterCritical{};
  };
  const FlutterCritical aligned = boundary(f), shifted = boundary(late);
  std::printf("loads %.0f us late: lambda_cr %.8g -> %.8g, M_cr %.6f -> %.6f (%+.4f)\n", delta * 1e6, aligned.lambda,
              shifted.lambda, aligned.mach, shifted.mach, shifted.mach - aligned.mach);
  EXPECT_LT(shifted.lambda / aligned.lambda - 1.0, -1e-4);
  EXPECT_LT(shifted.mach - aligned.mach, -1e-4);
}

TEST(ForcedMotion, TwoIdentificationsInterpolateInMach) {
  // Piston theory identified at M1 and M2 around its boundary (one tap of [q; q'] each, the
  // exact modal matrices): the interpolated model is piston theory with c(M) interpolated
  // linearly between them, whose boundary it returns exactly (the trapezoidal map, as above),
  // closer to piston theory's own than one identification at the case's Mach 2.3 scaled in
  // reduced time. At M1 and M2 it is that identification's model.
  const shell::ShellModel model = strip(20, Edges::clamped);
  const LinearFlutterSystem sys(model, kModes);
  const FlutterSetting s = setting(true);
  const PistonAerodynamics piston_aero(sys, piston(model));
  const auto exact = sweep_flutter(sys, piston_aero, s, FlutterParameter::mach, 1.5, 3.0, 16);
  ASSERT_TRUE(exact.critical);
  const double m1 = std::round(10.0 * exact.critical->mach) / 10.0 - 0.1, m2 = m1 + 0.2;
  const double dt = 1e-4;
  const auto one_tap = [&](double mach) {
    const AeroStateSpace a = piston_aero.at(s.flow(FlutterParameter::mach, mach));
    FirModel fir;
    fir.dt = dt;
    fir.taps = {Eigen::MatrixXd(kModes, 2 * kModes)};
    fir.taps[0] << a.D0, a.D1;
    return fir;
  };
  const MachInterpolatedAerodynamics two(one_tap(m1), s.flow(FlutterParameter::mach, m1), one_tap(m2),
                                         s.flow(FlutterParameter::mach, m2), DiscreteCoupling::simultaneous);
  const IdentifiedAerodynamics one(one_tap(2.3).state_space(), case_flow(), DiscreteCoupling::simultaneous);
  const auto a = sweep_flutter(sys, two, s, FlutterParameter::mach, 1.5, 3.0, 16);
  const auto b = sweep_flutter(sys, one, s, FlutterParameter::mach, 1.5, 3.0, 16);
  const auto reference =
      sweep_flutter(sys, InterpolatedDamping(piston_aero, m1, m2), s, FlutterParameter::mach, 1.5, 3.0, 16);
  ASSERT_TRUE(a.critical && b.critical && reference.critical);
  std::printf(
      "M_cr: identified at %.1f and %.1f %.8f, piston with c interpolated %.8f, identified at 2.3 %.8f, piston "
      "%.8f\n",
      m1, m2, a.critical->mach, reference.critical->mach, b.critical->mach, exact.critical->mach);
  EXPECT_NEAR(a.critical->mach, reference.critical->mach, 1e-6);
  EXPECT_LT(std::abs(a.critical->mach - exact.critical->mach), 0.1 * std::abs(b.critical->mach - exact.critical->mach));
  // At M1 the interpolation is the first identification's model, bit for bit in its roots.
  const FlowCondition at_m1 = s.flow(FlutterParameter::mach, m1);
  const IdentifiedAerodynamics first(one_tap(m1).state_space(), at_m1, DiscreteCoupling::simultaneous);
  EXPECT_EQ(two.roots(sys, at_m1), first.roots(sys, at_m1));
  // Models that cannot be interpolated are refused.
  EXPECT_THROW(MachInterpolatedAerodynamics(one_tap(m2), s.flow(FlutterParameter::mach, m2), one_tap(m1),
                                            s.flow(FlutterParameter::mach, m1), DiscreteCoupling::simultaneous),
               InputError);
  FlowCondition other = s.flow(FlutterParameter::mach, m2);
  other.speed *= 1.1;
  EXPECT_THROW(MachInterpolatedAerodynamics(one_tap(m1), at_m1, one_tap(m2), other, DiscreteCoupling::simultaneous),
               InputError);
  // The truncation check's model: the first half of the modes.
  EXPECT_EQ(two.truncated(3)->roots(sys.truncated(3), at_m1).size(), 3u);
}

TEST(ForcedMotion, TheStaggeredPathHasTheDriversPredictorLag) {
  // The staggered step's force is the linear prediction 2 f_n - f_{n-1}: its boundary
  // converges to the same continuous value as the simultaneous one, at first order or better,
  // and differs from it at a finite step.
  const shell::ShellModel model = strip(20, Edges::clamped);
  const LinearFlutterSystem sys(model, kModes);
  const FlutterSetting s = setting(true);
  const AeroStateSpace exact = PistonAerodynamics(sys, piston(model)).at(case_flow());
  double previous = 0.0;
  for (const double dt : {1e-4, 5e-5}) {
    FirModel known;
    known.dt = dt;
    known.taps = {Eigen::MatrixXd(kModes, 2 * kModes)};
    known.taps[0] << exact.D0, exact.D1;
    const IdentifiedAerodynamics simultaneous(known.state_space(), case_flow(), DiscreteCoupling::simultaneous);
    const IdentifiedAerodynamics staggered(known.state_space(), case_flow(), DiscreteCoupling::staggered);
    const auto a = sweep_flutter(sys, simultaneous, s, FlutterParameter::lambda, 0.0, 1500.0, 16);
    const auto b = sweep_flutter(sys, staggered, s, FlutterParameter::lambda, 0.0, 1500.0, 16);
    ASSERT_TRUE(a.critical && b.critical);
    const double difference = b.critical->lambda / a.critical->lambda - 1.0;
    std::printf("dt %.0e: lambda_cr simultaneous %.9g, staggered %.9g (%+.3e)\n", dt, a.critical->lambda,
                b.critical->lambda, difference);
    EXPECT_GT(std::abs(difference), 1e-6);
    if (previous != 0.0) {
      EXPECT_GT(previous / difference, 1.8);
    }
    previous = difference;
  }
}

TEST(ForcedMotion, AStaggeredStepIsTheDriversRecursion) {
  // T of the staggered scheme against its recursion written out: a_{n+1} = -K q_{n+1} + P,
  // P = 2 f_n - f_{n-1}, f_n = s (Dq q_n + Dv q'_n).
  const LinearFlutterSystem sys(strip(8, Edges::clamped), 4);
  const double dt = 1e-4, s = 2e4;
  FirModel fir;
  fir.dt = dt;
  fir.taps = {Eigen::MatrixXd::Random(4, 8)};
  const Eigen::MatrixXd T = discrete_step_matrix(sys, fir.state_space(), s, DiscreteCoupling::staggered);
  ASSERT_EQ(T.rows(), 16);
  const Eigen::MatrixXd& K = sys.stiffness();
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(4, 4);
  const double hh = 0.25 * dt * dt;
  Eigen::VectorXd q = Eigen::VectorXd::Random(4) * 1e-6, v = Eigen::VectorXd::Random(4) * 1e-3;
  Eigen::VectorXd acc = Eigen::VectorXd::Random(4), f_prev = Eigen::VectorXd::Random(4);
  Eigen::VectorXd Y(16);
  Y << q, v, acc, f_prev;
  for (int n = 0; n < 20; ++n) {
    const Eigen::VectorXd f = s * (fir.taps[0].leftCols(4) * q + fir.taps[0].rightCols(4) * v);
    const Eigen::VectorXd P = 2.0 * f - f_prev;
    const Eigen::VectorXd q1 = (I + hh * K).lu().solve(q + dt * v + hh * (acc + P));
    const Eigen::VectorXd a1 = -K * q1 + P;
    v += 0.5 * dt * (acc + a1);
    q = q1;
    acc = a1;
    f_prev = f;
    Y = T * Y;
    EXPECT_LT((Y.head(4) - q).norm(), 1e-10 * q.norm()) << "step " << n + 1;
    EXPECT_LT((Y.segment(4, 4) - v).norm(), 1e-10 * v.norm()) << "step " << n + 1;
  }
}

}  // namespace
}  // namespace shellflow::coupling
