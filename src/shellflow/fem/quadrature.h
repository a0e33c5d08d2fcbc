#pragma once
// Quadrature rules on the reference elements of shape_functions.h:
//   line        [-1, 1]            Gauss–Legendre, any number of points (weights sum to 2)
//   triangle    (0,0) (1,0) (0,1)  every degree 0..max_triangle_degree (weights sum to 1/2)
//   tetrahedron unit tetrahedron   every degree 0..max_tetrahedron_degree (weights sum to 1/6)
// Nothing is typed in from tables: Gauss rules are computed (Newton on Legendre polynomials,
// Golub–Welsch for Gauss–Jacobi), simplex rules are either collapsed (Duffy) products of
// Gauss–Jacobi and Gauss–Legendre rules, or, for low degrees, fully symmetric rules whose
// published values serve only as starting points of a Gauss–Newton solve of the moment
// equations (so every digit is computed). docs/fem.md lists the point counts.
//
// The cached accessors return references to rules built on first use (thread-safe) that
// live until the program ends.
#include <span>
#include <string_view>
#include <vector>

namespace shellflow::fem {

struct QuadratureRule {
  int dim = 0;
  /// Every polynomial of total degree <= degree is integrated exactly (up to rounding);
  /// may exceed the degree asked for.
  int degree = 0;
  /// size() x dim, row-major: point q's coordinate i is points[q*dim + i].
  std::vector<double> points;
  std::vector<double> weights;
  /// "Gauss-Legendre", "Gauss-Jacobi", "collapsed" or "symmetric".
  std::string_view family;

  int size() const { return static_cast<int>(weights.size()); }
  std::span<const double> point(int q) const {
    return {points.data() + static_cast<std::ptrdiff_t>(q) * dim, static_cast<std::size_t>(dim)};
  }
};

inline constexpr int max_line_points = 64;
inline constexpr int max_triangle_degree = 40;
inline constexpr int max_tetrahedron_degree = 30;

/// Gauss–Legendre rule with `npoints` points on [-1, 1], exact to degree 2 npoints - 1.
/// Cached. Throws InputError unless 1 <= npoints <= max_line_points.
const QuadratureRule& line_rule(int npoints);

/// Triangle rule exact to at least `degree` (0 <= degree <= max_triangle_degree), with
/// positive weights and interior points. Cached. Throws InputError out of range.
const QuadratureRule& triangle_rule(int degree);

/// Tetrahedron rule exact to at least `degree` (0 <= degree <= max_tetrahedron_degree),
/// with positive weights and interior points. Cached. Throws InputError out of range.
const QuadratureRule& tetrahedron_rule(int degree);

/// Rule exact to at least `degree` on the reference simplex of dimension dim (1, 2, 3); for
/// dim 1, the Gauss–Legendre rule with the fewest points.
const QuadratureRule& simplex_rule(int dim, int degree);

// --- building blocks (not cached; exposed for tests and special uses) -------------------

/// Gauss–Jacobi rule on [-1, 1] for the weight (1 - x)^alpha (1 + x)^beta (alpha, beta > -1),
/// by Golub–Welsch: nodes are the eigenvalues of the Jacobi matrix.
QuadratureRule gauss_jacobi_rule(int npoints, double alpha, double beta);

/// Gauss–Legendre rule on [-1, 1] by Newton iteration on P_n (not cached).
QuadratureRule gauss_legendre_rule(int npoints);

/// Collapsed (Duffy) rule with n points per direction: n^2 points on the triangle,
/// n^3 on the tetrahedron, exact to degree 2n - 1.
QuadratureRule collapsed_triangle_rule(int n);
QuadratureRule collapsed_tetrahedron_rule(int n);

}  // namespace shellflow::fem
