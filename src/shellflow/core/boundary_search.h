#pragma once
// The search for a stability boundary over one parameter (the study's, docs/flutter.md): the
// first sign change of the growth rate among the finished samples, its secant zero, and the
// refinement of the bracket by regula falsi with the Illinois modification, several samples
// per round. Knows nothing of runs or processes: the caller evaluates the values a round asks
// for and reports the new bracket.
#include <algorithm>
#include <optional>
#include <utility>
#include <vector>

namespace shellflow {

/// The first sign change of the growth rate among the samples that succeeded (`ok`), by
/// value: the adjacent pair, lower value first. S has `value`, `growth_rate` and `ok`.
template <class S>
std::optional<std::pair<S, S>> first_sign_change(const std::vector<S>& samples) {
  std::vector<S> ok;
  for (const S& s : samples)
    if (s.ok) ok.push_back(s);
  std::stable_sort(ok.begin(), ok.end(), [](const S& a, const S& b) { return a.value < b.value; });
  for (std::size_t i = 1; i < ok.size(); ++i)
    if ((ok[i - 1].growth_rate < 0.0) != (ok[i].growth_rate < 0.0)) return std::pair{ok[i - 1], ok[i]};
  return std::nullopt;
}

/// The zero of the line through (a, ga) and (b, gb): the boundary of a bracket.
double secant_zero(double a, double ga, double b, double gb);

/// Regula falsi with the Illinois modification on a bracket [a, b] of a sign change, `jobs`
/// values per round: the weighted secant estimate (kept 5 % of the width inside the bracket)
/// and jobs - 1 values splitting the bracket evenly. An end kept twice in a row has its growth
/// rate halved in the next estimate, so a convex or concave growth curve does not make one end
/// crawl.
class IllinoisRefinement {
 public:
  IllinoisRefinement(double tolerance, int max_rounds, int jobs);

  /// Whether [a, b] still needs a round (wider than the tolerance, rounds left).
  bool wants_round(double a, double b) const;
  /// The values of the next round on [a, b] with growth rates ga, gb (sorted, distinct by
  /// 1e-3 of the width).
  std::vector<double> next_values(double a, double ga, double b, double gb) const;

  /// What a round did to the bracket.
  enum class Outcome {
    narrowed,  ///< one end or both moved: refine on
    stalled,   ///< both ends kept: every value inside failed; stop with this bracket
  };
  /// Records a round that took [a, b] to [a2, b2] (the same bracket when nothing changed).
  Outcome record(double a, double b, double a2, double b2);
  int rounds() const { return rounds_; }

 private:
  double tolerance_;
  int max_rounds_, jobs_;
  int rounds_ = 0;
  double weight_a_ = 1.0, weight_b_ = 1.0;
  int last_kept_ = -1;  // 0: a, 1: b, -1: neither
};

}  // namespace shellflow
