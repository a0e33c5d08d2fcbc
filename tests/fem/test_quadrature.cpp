// Quadrature rules: exactness on every monomial up to the stated degree (against closed-form
// integrals), a measurable defect at the next degree (so the stated degree is the real one),
// positive weights, interior points, caching and thread safety.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <thread>
#include <vector>

#include "shellflow/core/error.h"
#include "shellflow/fem/quadrature.h"

namespace shellflow::fem {
namespace {

// ∫ x^a y^b over the unit triangle = a! b! / (a+b+2)!, ∫ x^a y^b z^c over the unit
// tetrahedron = a! b! c! / (a+b+c+3)!, evaluated in long double through the Gamma function
// (independent of the library's own product formula).
double exact_simplex_integral(int dim, const std::array<int, 3>& e) {
  long double lg = 0.0L;
  int n = 0;
  for (int k = 0; k < dim; ++k) {
    lg += std::lgamma(static_cast<long double>(e[k]) + 1.0L);
    n += e[k];
  }
  lg -= std::lgamma(static_cast<long double>(n + dim) + 1.0L);
  return static_cast<double>(std::exp(lg));
}

std::vector<std::array<int, 3>> monomials_of_degree(int dim, int degree) {
  if (dim == 1) return {{degree, 0, 0}};
  std::vector<std::array<int, 3>> m;
  for (int a = 0; a <= degree; ++a) {
    if (dim == 2) {
      m.push_back({a, degree - a, 0});
    } else {
      for (int b = 0; b <= degree - a; ++b) m.push_back({a, b, degree - a - b});
    }
  }
  return m;
}

/// For each degree 0..max_degree, the largest relative error of the rule over the monomials
/// of exactly that degree.
std::vector<double> relative_errors_by_degree(const QuadratureRule& rule, int max_degree) {
  const int dim = rule.dim, np = rule.size(), np1 = max_degree + 1;
  std::vector<double> pw(static_cast<std::size_t>(np) * dim * np1);  // x_k^e per point
  const auto at = [&](int q, int k, int e) -> double& { return pw[(static_cast<std::size_t>(q) * dim + k) * np1 + e]; };
  for (int q = 0; q < np; ++q)
    for (int k = 0; k < dim; ++k) {
      at(q, k, 0) = 1.0;
      for (int e = 1; e <= max_degree; ++e) at(q, k, e) = at(q, k, e - 1) * rule.point(q)[k];
    }
  std::vector<double> worst(np1, 0.0);
  for (int d = 0; d <= max_degree; ++d)
    for (const auto& e : monomials_of_degree(dim, d)) {
      double sum = 0.0;
      for (int q = 0; q < np; ++q) {
        double v = rule.weights[q];
        for (int k = 0; k < dim; ++k) v *= at(q, k, e[k]);
        sum += v;
      }
      const double exact = exact_simplex_integral(dim, e);
      worst[d] = std::max(worst[d], std::abs(sum - exact) / exact);
    }
  return worst;
}

void check_simplex_rule(const QuadratureRule& rule, int dim, int asked_degree) {
  SCOPED_TRACE("rule for degree " + std::to_string(asked_degree) + " (" + std::string(rule.family) + ", " +
               std::to_string(rule.size()) + " points)");
  ASSERT_EQ(rule.dim, dim);
  ASSERT_GE(rule.degree, std::max(asked_degree, 1));
  ASSERT_EQ(rule.points.size(), rule.weights.size() * static_cast<std::size_t>(dim));
  double sum = 0.0;
  for (int i = 0; i < rule.size(); ++i) {
    EXPECT_GT(rule.weights[i], 0.0) << "weight " << i;
    sum += rule.weights[i];
    double s = 0.0;
    for (int k = 0; k < dim; ++k) {
      EXPECT_GT(rule.point(i)[k], 0.0) << "point " << i;
      s += rule.point(i)[k];
    }
    EXPECT_LT(s, 1.0) << "point " << i;
  }
  EXPECT_NEAR(sum, dim == 2 ? 0.5 : 1.0 / 6.0, 1e-14);
  const auto err = relative_errors_by_degree(rule, rule.degree + 1);
  for (int d = 0; d <= rule.degree; ++d) EXPECT_LT(err[d], 4e-14) << "monomials of degree " << d;
  // The defect at degree + 1 shrinks like 4^-n with the points per direction; below 1e-11
  // it can no longer be told from rounding, so it is checked up to degree 35.
  if (rule.degree <= 35) {
    EXPECT_GT(err[rule.degree + 1], 1e-11) << "rule is exact beyond its stated degree " << rule.degree;
  }
}

TEST(GaussLegendre, ExactToDegree2nMinus1AndNotAt2n) {
  for (int n = 1; n <= max_line_points; ++n) {
    SCOPED_TRACE("n = " + std::to_string(n));
    const QuadratureRule& rule = line_rule(n);
    ASSERT_EQ(rule.size(), n);
    EXPECT_EQ(rule.degree, 2 * n - 1);
    for (int i = 0; i < n; ++i) {
      EXPECT_GT(rule.weights[i], 0.0);
      EXPECT_GT(rule.point(i)[0], -1.0);
      EXPECT_LT(rule.point(i)[0], 1.0);
      if (i > 0) {
        EXPECT_GT(rule.point(i)[0], rule.point(i - 1)[0]);
      }
    }
    // Monomials of (1 + x) are positive on [-1, 1], so errors can be measured relatively:
    // ∫ (1 + x)^k dx = 2^(k+1) / (k + 1).
    const auto rel_error = [&](int k) {
      double q = 0.0;
      for (int i = 0; i < n; ++i) q += rule.weights[i] * std::pow(1.0 + rule.point(i)[0], k);
      const double exact = std::pow(2.0, k + 1) / (k + 1);
      return std::abs(q - exact) / exact;
    };
    for (int k = 0; k <= 2 * n - 1; ++k) EXPECT_LT(rel_error(k), 1e-13) << "degree " << k;
    if (n <= 10) {
      EXPECT_GT(rel_error(2 * n), 1e-11) << "exact beyond degree 2n-1";
    }
  }
}

TEST(GaussJacobi, ExactForItsWeightToDegree2nMinus1) {
  // ∫ (1-x)^alpha (1+x)^k dx over [-1, 1] = 2^(alpha+k+1) alpha! k! / (alpha+k+1)!.
  for (int alpha : {0, 1, 2}) {
    for (int n = 1; n <= 25; ++n) {
      SCOPED_TRACE("alpha = " + std::to_string(alpha) + ", n = " + std::to_string(n));
      const QuadratureRule rule = gauss_jacobi_rule(n, alpha, 0.0);
      ASSERT_EQ(rule.size(), n);
      for (int k = 0; k <= 2 * n; ++k) {
        double q = 0.0;
        for (int i = 0; i < n; ++i) {
          EXPECT_GT(rule.weights[i], 0.0);
          q += rule.weights[i] * std::pow(1.0 + rule.point(i)[0], k);
        }
        const double exact = std::exp((alpha + k + 1) * std::log(2.0) + std::lgamma(alpha + 1.0) +
                                      std::lgamma(k + 1.0) - std::lgamma(alpha + k + 2.0));
        const double err = std::abs(q - exact) / exact;
        if (k < 2 * n) {
          EXPECT_LT(err, 1e-13) << "degree " << k;
        } else if (n <= 10) {
          EXPECT_GT(err, 1e-11) << "exact beyond degree 2n-1";
        }
      }
    }
  }
}

TEST(GaussJacobi, WithZeroExponentsIsGaussLegendre) {
  for (int n = 1; n <= 30; ++n) {
    const QuadratureRule gj = gauss_jacobi_rule(n, 0.0, 0.0);
    const QuadratureRule& gl = line_rule(n);
    for (int i = 0; i < n; ++i) {
      EXPECT_NEAR(gj.points[i], gl.points[i], 1e-14) << "n " << n << " node " << i;
      EXPECT_NEAR(gj.weights[i], gl.weights[i], 1e-14) << "n " << n << " node " << i;
    }
  }
}

TEST(TriangleRules, EveryDegreeIsExactToItsStatedDegreeWithPositiveWeights) {
  for (int d = 0; d <= max_triangle_degree; ++d) check_simplex_rule(triangle_rule(d), 2, d);
}

TEST(TetrahedronRules, EveryDegreeIsExactToItsStatedDegreeWithPositiveWeights) {
  for (int d = 0; d <= max_tetrahedron_degree; ++d) check_simplex_rule(tetrahedron_rule(d), 3, d);
}

TEST(CollapsedRules, AreExactToDegree2nMinus1) {
  for (int n = 1; n <= 8; ++n) {
    check_simplex_rule(collapsed_triangle_rule(n), 2, 2 * n - 1);
    check_simplex_rule(collapsed_tetrahedron_rule(n), 3, 2 * n - 1);
  }
}

// Symmetric rules map onto themselves under every permutation of the barycentric
// coordinates, so element integrals do not depend on how the vertices are numbered.
TEST(SymmetricRules, AreInvariantUnderVertexPermutations) {
  const auto check = [](const QuadratureRule& rule) {
    const int dim = rule.dim;
    std::vector<int> perm(dim + 1);
    for (int k = 0; k <= dim; ++k) perm[k] = k;
    do {
      for (int i = 0; i < rule.size(); ++i) {
        std::array<double, 4> L{};
        L[0] = 1.0;
        for (int k = 0; k < dim; ++k) {
          L[k + 1] = rule.point(i)[k];
          L[0] -= L[k + 1];
        }
        bool found = false;
        for (int j = 0; j < rule.size() && !found; ++j) {
          bool same = std::abs(rule.weights[j] - rule.weights[i]) < 1e-15;
          for (int k = 0; k < dim && same; ++k) same = std::abs(rule.point(j)[k] - L[perm[k + 1]]) < 1e-14;
          found = same;
        }
        EXPECT_TRUE(found) << "image of point " << i << " missing, degree " << rule.degree;
      }
    } while (std::next_permutation(perm.begin(), perm.end()));
  };
  int checked = 0;
  for (int d = 0; d <= max_triangle_degree; ++d)
    if (triangle_rule(d).family == "symmetric") {
      check(triangle_rule(d));
      ++checked;
    }
  for (int d = 0; d <= max_tetrahedron_degree; ++d)
    if (tetrahedron_rule(d).family == "symmetric") {
      check(tetrahedron_rule(d));
      ++checked;
    }
  EXPECT_GE(checked, 10);
}

TEST(QuadratureCache, ReturnsTheSameRuleOnEveryCall) {
  EXPECT_EQ(&triangle_rule(6), &triangle_rule(6));
  EXPECT_EQ(&tetrahedron_rule(8), &tetrahedron_rule(8));
  EXPECT_EQ(&line_rule(5), &line_rule(5));
  EXPECT_EQ(&simplex_rule(2, 4), &triangle_rule(4));
  EXPECT_EQ(&simplex_rule(3, 4), &tetrahedron_rule(4));
  EXPECT_EQ(&simplex_rule(1, 7), &line_rule(4));
}

TEST(QuadratureCache, ConcurrentFirstUsesBuildEachRuleOnce) {
  constexpr int kThreads = 8;
  std::array<std::vector<const QuadratureRule*>, kThreads> seen;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([t, &seen] {
      for (int d = 0; d <= max_tetrahedron_degree; ++d) {
        const int deg = (d + 3 * t) % (max_tetrahedron_degree + 1);  // vary the order
        seen[t].push_back(&tetrahedron_rule(deg));
        seen[t].push_back(&triangle_rule(deg));
      }
    });
  for (auto& th : threads) th.join();
  std::set<const QuadratureRule*> distinct;
  for (const auto& s : seen) distinct.insert(s.begin(), s.end());
  EXPECT_EQ(distinct.size(), 2u * (max_tetrahedron_degree + 1));
  for (const auto* r : distinct) EXPECT_GT(r->size(), 0);
}

TEST(QuadratureErrors, OutOfRangeRequestsThrowInputError) {
  EXPECT_THROW(triangle_rule(-1), InputError);
  EXPECT_THROW(triangle_rule(max_triangle_degree + 1), InputError);
  EXPECT_THROW(tetrahedron_rule(max_tetrahedron_degree + 1), InputError);
  EXPECT_THROW(line_rule(0), InputError);
  EXPECT_THROW(line_rule(max_line_points + 1), InputError);
  EXPECT_THROW(simplex_rule(4, 2), InputError);
  EXPECT_THROW(gauss_jacobi_rule(3, -1.0, 0.0), InputError);
}

}  // namespace
}  // namespace shellflow::fem
