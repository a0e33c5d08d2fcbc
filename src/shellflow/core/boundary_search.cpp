#include "shellflow/core/boundary_search.h"

#include <cmath>

#include "shellflow/core/error.h"

namespace shellflow {

double secant_zero(double a, double ga, double b, double gb) { return a - ga * (b - a) / (gb - ga); }

IllinoisRefinement::IllinoisRefinement(double tolerance, int max_rounds, int jobs)
    : tolerance_(tolerance), max_rounds_(max_rounds), jobs_(jobs) {
  if (!(tolerance > 0.0) || max_rounds < 0 || jobs < 1)
    throw Error("IllinoisRefinement: tolerance must be > 0, max_rounds >= 0 and jobs >= 1");
}

bool IllinoisRefinement::wants_round(double a, double b) const { return b - a > tolerance_ && rounds_ < max_rounds_; }

std::vector<double> IllinoisRefinement::next_values(double a, double ga, double b, double gb) const {
  const double w = b - a;
  const double wa = ga * weight_a_, wb = gb * weight_b_;
  std::vector<double> next{std::clamp(secant_zero(a, wa, b, wb), a + 0.05 * w, b - 0.05 * w)};
  for (int k = 1; k < jobs_; ++k) next.push_back(a + w * k / jobs_);
  std::sort(next.begin(), next.end());
  next.erase(std::unique(next.begin(), next.end(), [&](double p, double q) { return std::abs(p - q) < 1e-3 * w; }),
             next.end());
  return next;
}

IllinoisRefinement::Outcome IllinoisRefinement::record(double a, double b, double a2, double b2) {
  ++rounds_;
  const bool a_kept = a2 == a, b_kept = b2 == b;
  if (a_kept && b_kept) return Outcome::stalled;
  const int kept = a_kept ? 0 : b_kept ? 1 : -1;
  weight_a_ = kept == 0 ? (last_kept_ == 0 ? 0.5 * weight_a_ : weight_a_) : 1.0;
  weight_b_ = kept == 1 ? (last_kept_ == 1 ? 0.5 * weight_b_ : weight_b_) : 1.0;
  last_kept_ = kept;
  return Outcome::narrowed;
}

}  // namespace shellflow
