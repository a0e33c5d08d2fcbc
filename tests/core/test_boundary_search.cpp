// The study's boundary search (core/boundary_search.h) on growth curves with known zeros.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "shellflow/core/boundary_search.h"
#include "shellflow/core/error.h"

namespace shellflow {
namespace {

struct Sample {
  double value = 0.0;
  double growth_rate = 0.0;
  bool ok = true;
};

TEST(BoundarySearch, TheFirstSignChangeIsFoundAmongTheSuccessfulSamplesByValue) {
  // Out of order, a failed sample between the two sides, a second sign change further up.
  const std::vector<Sample> samples{{3.0, 2.0}, {1.0, -1.0}, {2.5, 9.0, false}, {2.0, -0.5}, {5.0, -1.0}};
  const auto b = first_sign_change(samples);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->first.value, 2.0);
  EXPECT_EQ(b->second.value, 3.0);
  EXPECT_FALSE(first_sign_change(std::vector<Sample>{{1.0, -1.0}, {2.0, -2.0}, {3.0, 5.0, false}}));
  EXPECT_FALSE(first_sign_change(std::vector<Sample>{}));
  // Zero counts as not negative: the boundary between -1 and 0 is 0 itself.
  const auto z = first_sign_change(std::vector<Sample>{{1.0, -1.0}, {2.0, 0.0}});
  ASSERT_TRUE(z);
  EXPECT_DOUBLE_EQ(secant_zero(z->first.value, z->first.growth_rate, z->second.value, z->second.growth_rate), 2.0);
}

TEST(BoundarySearch, TheSecantZeroOfALineIsItsRoot) {
  // g = 3 (x - 1.25): exact from any two points on either side.
  const auto g = [](double x) { return 3.0 * (x - 1.25); };
  EXPECT_DOUBLE_EQ(secant_zero(0.0, g(0.0), 2.0, g(2.0)), 1.25);
  EXPECT_DOUBLE_EQ(secant_zero(1.0, g(1.0), 4.0, g(4.0)), 1.25);
}

// Runs the refinement as the study does on g from the bracket [lo, hi]; returns the rounds and
// the final bracket.
struct Search {
  int rounds = 0;
  double a = 0.0, b = 0.0;
  int evaluations = 0;
};
Search search(const std::function<double(double)>& g, double lo, double hi, double tolerance, int max_rounds,
              int jobs) {
  std::vector<Sample> samples{{lo, g(lo)}, {hi, g(hi)}};
  IllinoisRefinement refinement(tolerance, max_rounds, jobs);
  auto bracket = first_sign_change(samples);
  Search s;
  while (bracket && refinement.wants_round(bracket->first.value, bracket->second.value)) {
    const auto [a, b] = *bracket;
    const std::vector<double> next = refinement.next_values(a.value, a.growth_rate, b.value, b.growth_rate);
    EXPECT_LE(next.size(), std::size_t(jobs));
    for (const double x : next) {
      EXPECT_GT(x, a.value);
      EXPECT_LT(x, b.value);
      samples.push_back({x, g(x)});
      ++s.evaluations;
    }
    bracket = first_sign_change(samples);
    if (refinement.record(a.value, b.value, bracket->first.value, bracket->second.value) ==
        IllinoisRefinement::Outcome::stalled)
      break;
  }
  s.rounds = refinement.rounds();
  s.a = bracket->first.value;
  s.b = bracket->second.value;
  return s;
}

TEST(BoundarySearch, IllinoisNarrowsBothEndsOfAConvexCurveFast) {
  // g = exp(4 x) - 2, zero at ln(2)/4: plain regula falsi keeps the upper end for ever (the
  // curve is convex) and the bracket never gets narrower than the zero's distance to 1.
  const auto g = [](double x) { return std::exp(4.0 * x) - 2.0; };
  const double zero = std::log(2.0) / 4.0;
  const Search s = search(g, 0.0, 1.0, 1e-6, 60, 1);
  EXPECT_LE(s.b - s.a, 1e-6);
  EXPECT_LE(s.a, zero);
  EXPECT_GE(s.b, zero);
  // Illinois converges superlinearly: a dozen rounds, where bisection needs 20 and plain regula
  // falsi about 60 without reaching the tolerance.
  EXPECT_LE(s.rounds, 14);
}

TEST(BoundarySearch, SeveralJobsSplitTheBracketAndEndWithinTheTolerance) {
  const auto g = [](double x) { return std::tanh(3.0 * (x - 2.3)); };
  const Search one = search(g, 1.0, 4.0, 1e-4, 60, 1);
  const Search four = search(g, 1.0, 4.0, 1e-4, 60, 4);
  for (const Search& s : {one, four}) {
    EXPECT_LE(s.b - s.a, 1e-4);
    EXPECT_LE(s.a, 2.3);
    EXPECT_GE(s.b, 2.3);
  }
  EXPECT_LE(four.rounds, one.rounds);
}

TEST(BoundarySearch, TheRoundsStopAtTheirLimitAndWhenTheRunsInsideFail) {
  const auto g = [](double x) { return x - 0.3; };
  EXPECT_EQ(search(g, 0.0, 1.0, 1e-12, 2, 1).rounds, 2);
  // Every value inside failed: the bracket stays and the search stops after one round.
  IllinoisRefinement refinement(1e-6, 10, 2);
  EXPECT_EQ(refinement.record(0.0, 1.0, 0.0, 1.0), IllinoisRefinement::Outcome::stalled);
  EXPECT_EQ(refinement.rounds(), 1);
  EXPECT_EQ(refinement.record(0.0, 1.0, 0.2, 1.0), IllinoisRefinement::Outcome::narrowed);
  EXPECT_FALSE(IllinoisRefinement(1e-6, 0, 1).wants_round(0.0, 1.0));
  EXPECT_THROW(IllinoisRefinement(0.0, 10, 1), Error);
  EXPECT_THROW(IllinoisRefinement(1e-6, 10, 0), Error);
}

TEST(BoundarySearch, AnEndKeptTwiceCountsHalfInTheNextEstimate) {
  // Bracket [0, 1] with growth rates -1 and 3: the plain secant is at 0.25; after the upper end
  // was kept twice its rate counts 1.5 and the estimate moves to 0.4.
  IllinoisRefinement refinement(1e-9, 10, 1);
  EXPECT_DOUBLE_EQ(refinement.next_values(0.0, -1.0, 1.0, 3.0).at(0), 0.25);
  refinement.record(-1.0, 1.0, 0.0, 1.0);  // the lower end moved, the upper kept
  EXPECT_DOUBLE_EQ(refinement.next_values(0.0, -1.0, 1.0, 3.0).at(0), 0.25);
  refinement.record(-0.5, 1.0, 0.0, 1.0);  // kept again: halved
  EXPECT_DOUBLE_EQ(refinement.next_values(0.0, -1.0, 1.0, 3.0).at(0), 0.4);
  refinement.record(0.0, 1.0, 0.0, 0.5);  // now the lower end is kept: the upper counts fully
  EXPECT_DOUBLE_EQ(refinement.next_values(0.0, -1.0, 1.0, 3.0).at(0), 0.25);
}

}  // namespace
}  // namespace shellflow
