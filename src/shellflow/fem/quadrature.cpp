#include "shellflow/fem/quadrature.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <numbers>
#include <stdexcept>

#include "shellflow/core/error.h"

namespace shellflow::fem {
namespace {

// ∫ over the reference simplex of x^e0 y^e1 (z^e2) = e0! e1! (e2!) / (|e| + dim)!.
double simplex_monomial_integral(int dim, const int* e) {
  // a! b! / (a + b)! as a product of ratios, which stays accurate for large exponents.
  const auto ratio = [](int a, int b) {
    double r = 1.0;
    for (int i = 1; i <= b; ++i) r *= static_cast<double>(i) / (a + i);
    return r;
  };
  double v = 1.0;
  int n = e[0];
  for (int k = 1; k < dim; ++k) {
    v *= ratio(n, e[k]);
    n += e[k];
  }
  for (int k = 1; k <= dim; ++k) v /= (n + k);
  return v;
}

// --- fully symmetric rules ------------------------------------------------------------------
// A symmetric rule is a set of orbits: all distinct permutations of a barycentric tuple whose
// entries are affine in up to two parameters (a, b), with one weight per orbit. Starting from
// published values, Gauss–Newton on the moment equations of every monomial up to the degree
// refines parameters and weights to machine precision; a rule that does not converge is a
// bug and throws.

struct Affine {
  double c, da, db;  // c + da * a + db * b
};

enum class Orbit { s3, s21, s111, s4, s31, s22, s211 };

struct OrbitStart {
  Orbit orbit;
  double a, b;  // starting parameters (unused ones ignored)
  double w;     // starting weight of each point, as a fraction of the simplex's volume
};

struct OrbitShape {
  int num_params;
  std::vector<int> labels;      // sorted pattern whose distinct permutations are the points
  std::vector<Affine> entries;  // value of each label
};

OrbitShape orbit_shape(Orbit o) {
  const Affine a{0, 1, 0}, b{0, 0, 1};
  switch (o) {
    case Orbit::s3:
      return {0, {0, 0, 0}, {{1.0 / 3.0, 0, 0}}};
    case Orbit::s21:
      return {1, {0, 0, 1}, {a, {1, -2, 0}}};
    case Orbit::s111:
      return {2, {0, 1, 2}, {a, b, {1, -1, -1}}};
    case Orbit::s4:
      return {0, {0, 0, 0, 0}, {{0.25, 0, 0}}};
    case Orbit::s31:
      return {1, {0, 0, 0, 1}, {a, {1, -3, 0}}};
    case Orbit::s22:
      return {1, {0, 0, 1, 1}, {a, {0.5, -1, 0}}};
    case Orbit::s211:
      return {2, {0, 0, 1, 2}, {a, b, {1, -2, -1}}};
  }
  throw std::logic_error("unknown orbit");
}

// Exponent vectors of every monomial of total degree <= degree in dim variables.
std::vector<std::array<int, 3>> monomials(int dim, int degree) {
  std::vector<std::array<int, 3>> m;
  for (int a = 0; a <= degree; ++a)
    for (int b = 0; b <= (dim >= 2 ? degree - a : 0); ++b)
      for (int c = 0; c <= (dim == 3 ? degree - a - b : 0); ++c) m.push_back({a, b, c});
  return m;
}

QuadratureRule symmetric_rule(int dim, int degree, const std::vector<OrbitStart>& start) {
  const double volume = dim == 2 ? 0.5 : 1.0 / 6.0;

  // Points of each orbit: coordinates x_k = L_{k+1} as affine functions of the orbit's (a, b).
  struct OrbitPoints {
    int num_params;
    std::vector<std::array<Affine, 3>> x;
  };
  std::vector<OrbitPoints> orbits;
  std::vector<double> u;  // unknowns: per orbit its parameters, then its weight
  for (const auto& s : start) {
    OrbitShape shape = orbit_shape(s.orbit);
    if (static_cast<int>(shape.labels.size()) != dim + 1) throw std::logic_error("orbit of the wrong dimension");
    OrbitPoints op{shape.num_params, {}};
    std::vector<int> perm = shape.labels;
    do {
      std::array<Affine, 3> x{};
      for (int k = 0; k < dim; ++k) x[k] = shape.entries[perm[k + 1]];
      op.x.push_back(x);
    } while (std::next_permutation(perm.begin(), perm.end()));
    orbits.push_back(op);
    if (shape.num_params >= 1) u.push_back(s.a);
    if (shape.num_params >= 2) u.push_back(s.b);
    u.push_back(s.w * volume);
  }

  const auto mono = monomials(dim, degree);
  const int nm = static_cast<int>(mono.size());
  const int nu = static_cast<int>(u.size());
  Eigen::VectorXd r(nm);
  Eigen::MatrixXd J(nm, nu);

  const auto evaluate = [&] {
    r.setZero();
    J.setZero();
    for (int m = 0; m < nm; ++m) r[m] = -simplex_monomial_integral(dim, mono[m].data());
    int col = 0;
    for (const auto& o : orbits) {
      const double a = o.num_params >= 1 ? u[col] : 0.0;
      const double b = o.num_params >= 2 ? u[col + 1] : 0.0;
      const int wcol = col + o.num_params;
      const double w = u[wcol];
      for (const auto& xa : o.x) {
        double x[3] = {1, 1, 1}, dxa[3] = {0, 0, 0}, dxb[3] = {0, 0, 0};
        for (int k = 0; k < dim; ++k) {
          x[k] = xa[k].c + xa[k].da * a + xa[k].db * b;
          dxa[k] = xa[k].da;
          dxb[k] = xa[k].db;
        }
        for (int m = 0; m < nm; ++m) {
          const auto& e = mono[m];
          double p = 1.0, dpa = 0.0, dpb = 0.0;
          for (int k = 0; k < dim; ++k) {
            // product rule: d(p * x^e)/da = dp/da x^e + p e x^(e-1) dx/da
            const double xe = std::pow(x[k], e[k]);
            const double dxe = e[k] == 0 ? 0.0 : e[k] * std::pow(x[k], e[k] - 1);
            dpa = dpa * xe + p * dxe * dxa[k];
            dpb = dpb * xe + p * dxe * dxb[k];
            p *= xe;
          }
          r[m] += w * p;
          J(m, wcol) += p;
          if (o.num_params >= 1) J(m, col) += w * dpa;
          if (o.num_params >= 2) J(m, col + 1) += w * dpb;
        }
      }
      col = wcol + 1;
    }
  };

  for (int it = 0; it < 50; ++it) {
    evaluate();
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(J);
    if (qr.rank() < nu) throw std::logic_error("symmetric quadrature: singular moment Jacobian");
    const Eigen::VectorXd du = qr.solve(-r);
    for (int i = 0; i < nu; ++i) u[i] += du[i];
    if (du.lpNorm<Eigen::Infinity>() < 1e-15) break;
  }
  evaluate();
  if (r.lpNorm<Eigen::Infinity>() > 1e-14)
    throw std::logic_error("symmetric quadrature: moment equations not satisfied");

  QuadratureRule rule;
  rule.dim = dim;
  rule.degree = degree;
  rule.family = "symmetric";
  int col = 0;
  for (const auto& o : orbits) {
    const double a = o.num_params >= 1 ? u[col] : 0.0;
    const double b = o.num_params >= 2 ? u[col + 1] : 0.0;
    const double w = u[col + o.num_params];
    for (const auto& xa : o.x) {
      for (int k = 0; k < dim; ++k) rule.points.push_back(xa[k].c + xa[k].da * a + xa[k].db * b);
      rule.weights.push_back(w);
    }
    col += o.num_params + 1;
  }
  return rule;
}

// Starting values: triangle rules of Dunavant (1985, IJNME 21:1129), all positive weights
// and interior points; S21(a) = (a, a, 1-2a), S111(a, b) = (a, b, 1-a-b).
QuadratureRule symmetric_triangle_rule(int degree) {
  switch (degree) {
    case 1:
      return symmetric_rule(2, 1, {{Orbit::s3, 0, 0, 1.0}});
    case 2:
      return symmetric_rule(2, 2, {{Orbit::s21, 1.0 / 6.0, 0, 1.0 / 3.0}});
    case 4:
      return symmetric_rule(2, 4,
                            {{Orbit::s21, 0.445948490915965, 0, 0.223381589678011},
                             {Orbit::s21, 0.091576213509771, 0, 0.109951743655322}});
    case 5:
      return symmetric_rule(2, 5,
                            {{Orbit::s3, 0, 0, 0.225},
                             {Orbit::s21, 0.470142064105115, 0, 0.132394152788506},
                             {Orbit::s21, 0.101286507323456, 0, 0.125939180544827}});
    case 6:
      return symmetric_rule(2, 6,
                            {{Orbit::s21, 0.249286745170910, 0, 0.116786275726379},
                             {Orbit::s21, 0.063089014491502, 0, 0.050844906370207},
                             {Orbit::s111, 0.053145049844817, 0.310352451033784, 0.082851075618374}});
    case 8:
      return symmetric_rule(2, 8,
                            {{Orbit::s3, 0, 0, 0.144315607677787},
                             {Orbit::s21, 0.459292588292723, 0, 0.095091634267285},
                             {Orbit::s21, 0.170569307751760, 0, 0.103217370534718},
                             {Orbit::s21, 0.050547228317031, 0, 0.032458497623198},
                             {Orbit::s111, 0.008394777409958, 0.263112829634638, 0.027230314174435}});
    default:
      throw std::logic_error("no symmetric triangle rule of this degree");
  }
}

// Starting values: tetrahedron rules of Keast (1986, CMAME 55:339) and Walkington (2000),
// all positive weights and interior points; S31(a) = (a, a, a, 1-3a),
// S22(a) = (a, a, 1/2-a, 1/2-a), S211(a, b) = (a, a, b, 1-2a-b).
QuadratureRule symmetric_tetrahedron_rule(int degree) {
  switch (degree) {
    case 1:
      return symmetric_rule(3, 1, {{Orbit::s4, 0, 0, 1.0}});
    case 2:
      return symmetric_rule(3, 2, {{Orbit::s31, (5.0 - std::sqrt(5.0)) / 20.0, 0, 0.25}});
    case 5:
      return symmetric_rule(3, 5,
                            {{Orbit::s31, 0.0927352503108912, 0, 0.0734930431163620},
                             {Orbit::s31, 0.3108859192633006, 0, 0.1126879257180159},
                             {Orbit::s22, 0.0455037041256496, 0, 0.0425460207770815}});
    case 6:
      return symmetric_rule(3, 6,
                            {{Orbit::s31, 0.214602871259151684, 0, 0.0399227502581679},
                             {Orbit::s31, 0.0406739585346113397, 0, 0.0100772110553207},
                             {Orbit::s31, 0.322337890142275646, 0, 0.0553571815436544},
                             {Orbit::s211, 0.0636610018750175299, 0.269672331458315867, 0.0482142857142857}});
    default:
      throw std::logic_error("no symmetric tetrahedron rule of this degree");
  }
}

// P_n^(alpha, beta)(x) by the three-term recurrence.
double jacobi_polynomial(int n, double alpha, double beta, double x) {
  if (n == 0) return 1.0;
  const double ab = alpha + beta;
  double p0 = 1.0, p1 = (alpha + 1.0) + 0.5 * (ab + 2.0) * (x - 1.0);
  for (int k = 2; k <= n; ++k) {
    const double s = 2.0 * k + ab;
    const double a1 = 2.0 * k * (k + ab) * (s - 2.0);
    const double a2 = (s - 1.0) * (s * (s - 2.0) * x + alpha * alpha - beta * beta);
    const double a3 = 2.0 * (k + alpha - 1.0) * (k + beta - 1.0) * s;
    const double p2 = (a2 * p1 - a3 * p0) / a1;
    p0 = p1;
    p1 = p2;
  }
  return p1;
}

// Maps a rule on [-1, 1] with weight (1-x)^alpha to [0, 1] with weight (1-s)^alpha.
void to_unit_interval(QuadratureRule& r, double alpha) {
  const double scale = std::pow(0.5, alpha + 1.0);
  for (auto& x : r.points) x = 0.5 * (1.0 + x);
  for (auto& w : r.weights) w *= scale;
}

void check_range(const char* what, int value, int lo, int hi) {
  if (value < lo || value > hi)
    throw_input_error("{} {} out of range: shellflow provides {} to {}", what, value, lo, hi);
}

// Rules built on first use; one once_flag per entry so that concurrent first uses of
// different degrees do not serialise on one lock longer than needed.
template <int N, class Build>
const QuadratureRule& cached(int index, Build&& build) {
  static std::array<std::once_flag, N> flags;
  static std::array<QuadratureRule, N> rules;
  std::call_once(flags[index], [&] { rules[index] = build(index); });
  return rules[index];
}

}  // namespace

QuadratureRule gauss_legendre_rule(int n) {
  if (n < 1) throw_input_error("Gauss-Legendre rule needs at least one point, got {}", n);
  QuadratureRule rule;
  rule.dim = 1;
  rule.degree = 2 * n - 1;
  rule.family = "Gauss-Legendre";
  rule.points.assign(n, 0.0);
  rule.weights.assign(n, 0.0);
  // P_n and P_n' at x by the three-term recurrence.
  const auto legendre = [n](double x, double& p, double& dp) {
    double p0 = 1.0, p1 = x;
    for (int k = 2; k <= n; ++k) {
      const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    p = n == 1 ? x : p1;
    const double pm1 = n == 1 ? 1.0 : p0;
    dp = n * (x * p - pm1) / (x * x - 1.0);
  };
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));  // Tricomi's guess
    double p = 0.0, dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      legendre(x, p, dp);
      const double dx = p / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    if (2 * i + 1 == n) x = 0.0;  // the middle root of odd n
    legendre(x, p, dp);
    const double w = 2.0 / ((1.0 - x * x) * dp * dp);
    rule.points[i] = -x;  // ascending order, exactly symmetric
    rule.points[n - 1 - i] = x;
    rule.weights[i] = rule.weights[n - 1 - i] = w;
  }
  return rule;
}

QuadratureRule gauss_jacobi_rule(int n, double alpha, double beta) {
  if (n < 1) throw_input_error("Gauss-Jacobi rule needs at least one point, got {}", n);
  if (!(alpha > -1.0 && beta > -1.0))
    throw_input_error("Gauss-Jacobi exponents must exceed -1, got {} and {}", alpha, beta);
  // Jacobi matrix of the monic Jacobi polynomials (Golub & Welsch 1969).
  Eigen::VectorXd diag(n), sub(std::max(n - 1, 1));
  const double ab = alpha + beta;
  for (int k = 0; k < n; ++k) {
    const double s = 2.0 * k + ab;
    diag[k] = k == 0 ? (beta - alpha) / (ab + 2.0) : (beta * beta - alpha * alpha) / (s * (s + 2.0));
  }
  for (int k = 1; k < n; ++k) {
    const double s = 2.0 * k + ab;
    sub[k - 1] = std::sqrt(4.0 * k * (k + alpha) * (k + beta) * (k + ab) / (s * s * (s + 1.0) * (s - 1.0)));
  }
  const double mu0 =
      std::pow(2.0, ab + 1.0) * std::tgamma(alpha + 1.0) * std::tgamma(beta + 1.0) / std::tgamma(ab + 2.0);
  QuadratureRule rule;
  rule.dim = 1;
  rule.degree = 2 * n - 1;
  rule.family = "Gauss-Jacobi";
  if (n == 1) {
    rule.points = {diag[0]};
    rule.weights = {mu0};
    return rule;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es;
  es.computeFromTridiagonal(diag, sub.head(n - 1), Eigen::ComputeEigenvectors);
  if (es.info() != Eigen::Success) throw std::runtime_error("Golub-Welsch eigensolver failed");
  // The eigenvalues are accurate to rounding but the weights from eigenvectors lose a few
  // digits for small weights: polish the nodes by Newton on P_n and take the weights from
  // the closed form  w = 2^(a+b+1) G(n+a+1) G(n+b+1) / (G(n+a+b+1) n! (1-x^2) P_n'(x)^2),
  // with P_n' = (n+a+b+1)/2 P_{n-1}^(a+1, b+1).
  const double log_c = (ab + 1.0) * std::log(2.0) + std::lgamma(n + alpha + 1.0) + std::lgamma(n + beta + 1.0) -
                       std::lgamma(n + ab + 1.0) - std::lgamma(n + 1.0);
  const auto derivative = [&](double x) {
    return 0.5 * (n + ab + 1.0) * jacobi_polynomial(n - 1, alpha + 1.0, beta + 1.0, x);
  };
  for (int i = 0; i < n; ++i) {
    double x = es.eigenvalues()[i];
    for (int it = 0; it < 3; ++it) x -= jacobi_polynomial(n, alpha, beta, x) / derivative(x);
    const double dp = derivative(x);
    rule.points.push_back(x);
    rule.weights.push_back(std::exp(log_c) / ((1.0 - x * x) * dp * dp));
  }
  return rule;
}

QuadratureRule collapsed_triangle_rule(int n) {
  // x = s, y = (1 - s) t with Jacobian (1 - s): Gauss–Jacobi(1, 0) in s, Legendre in t.
  QuadratureRule rs = gauss_jacobi_rule(n, 1.0, 0.0);
  QuadratureRule rt = gauss_legendre_rule(n);
  to_unit_interval(rs, 1.0);
  to_unit_interval(rt, 0.0);
  QuadratureRule rule;
  rule.dim = 2;
  rule.degree = 2 * n - 1;
  rule.family = "collapsed";
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double s = rs.points[i], t = rt.points[j];
      rule.points.insert(rule.points.end(), {s, (1.0 - s) * t});
      rule.weights.push_back(rs.weights[i] * rt.weights[j]);
    }
  return rule;
}

QuadratureRule collapsed_tetrahedron_rule(int n) {
  // x = r, y = (1 - r) s, z = (1 - r)(1 - s) t with Jacobian (1 - r)^2 (1 - s).
  QuadratureRule rr = gauss_jacobi_rule(n, 2.0, 0.0);
  QuadratureRule rs = gauss_jacobi_rule(n, 1.0, 0.0);
  QuadratureRule rt = gauss_legendre_rule(n);
  to_unit_interval(rr, 2.0);
  to_unit_interval(rs, 1.0);
  to_unit_interval(rt, 0.0);
  QuadratureRule rule;
  rule.dim = 3;
  rule.degree = 2 * n - 1;
  rule.family = "collapsed";
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const double r = rr.points[i], s = rs.points[j], t = rt.points[k];
        rule.points.insert(rule.points.end(), {r, (1.0 - r) * s, (1.0 - r) * (1.0 - s) * t});
        rule.weights.push_back(rr.weights[i] * rs.weights[j] * rt.weights[k]);
      }
  return rule;
}

const QuadratureRule& line_rule(int npoints) {
  check_range("Gauss-Legendre point count", npoints, 1, max_line_points);
  return cached<max_line_points + 1>(npoints, [](int n) { return gauss_legendre_rule(n); });
}

const QuadratureRule& triangle_rule(int degree) {
  check_range("triangle quadrature degree", degree, 0, max_triangle_degree);
  return cached<max_triangle_degree + 1>(degree, [](int d) {
    // Symmetric rules where one with no more points than the collapsed rule is known;
    // degree 3 uses the 6-point degree-4 rule and 7 the 16-point degree-8 rule, so that
    // low-order element matrices do not depend on the vertex numbering.
    switch (d) {
      case 0:
      case 1:
        return symmetric_triangle_rule(1);
      case 2:
        return symmetric_triangle_rule(2);
      case 3:
      case 4:
        return symmetric_triangle_rule(4);
      case 5:
        return symmetric_triangle_rule(5);
      case 6:
        return symmetric_triangle_rule(6);
      case 7:
      case 8:
        return symmetric_triangle_rule(8);
      default:
        return collapsed_triangle_rule(d / 2 + 1);
    }
  });
}

const QuadratureRule& tetrahedron_rule(int degree) {
  check_range("tetrahedron quadrature degree", degree, 0, max_tetrahedron_degree);
  return cached<max_tetrahedron_degree + 1>(degree, [](int d) {
    switch (d) {
      case 0:
      case 1:
        return symmetric_tetrahedron_rule(1);
      case 2:
        return symmetric_tetrahedron_rule(2);
      case 4:
      case 5:
        return symmetric_tetrahedron_rule(5);
      case 6:
        return symmetric_tetrahedron_rule(6);
      default:
        return collapsed_tetrahedron_rule(d / 2 + 1);
    }
  });
}

const QuadratureRule& simplex_rule(int dim, int degree) {
  switch (dim) {
    case 1:
      check_range("line quadrature degree", degree, 0, 2 * max_line_points - 1);
      return line_rule(degree / 2 + 1);
    case 2:
      return triangle_rule(degree);
    case 3:
      return tetrahedron_rule(degree);
    default:
      throw_input_error("no quadrature on simplices of dimension {}", dim);
  }
}

}  // namespace shellflow::fem
