// Shape functions of every element class, checked against Gmsh itself (node coordinates,
// Kronecker property, basis values and gradients) and against their defining properties
// (partition of unity, polynomial reproduction, derivatives by finite differences).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "gmsh_reference.h"
#include "shellflow/fem/reference_element.h"
#include "shellflow/fem/shape_functions.h"

namespace shellflow::fem {
namespace {

using testing::gmsh_element_properties;
using testing::gmsh_lagrange_basis;

template <class E>
class ShapeFunctionTest : public ::testing::Test {};

using Elements = ::testing::Types<Line2, Line3, Line4, Tri3, Tri6, Tri10, Tet4, Tet10, Tet20>;

struct ElementName {
  template <class E>
  static std::string GetName(int) {
    return reference_element(E::gmsh_type).name;
  }
};
TYPED_TEST_SUITE(ShapeFunctionTest, Elements, ElementName);

/// Random points of the reference element, or of the element enlarged by `margin` (the
/// formulas are polynomials and are also used outside, by point location).
template <class E>
std::vector<std::array<double, E::dim>> random_points(int count, double margin = 0.0, unsigned seed = 12345) {
  std::mt19937 rng(seed);
  std::vector<std::array<double, E::dim>> pts;
  while (static_cast<int>(pts.size()) < count) {
    std::array<double, E::dim> x{};
    if constexpr (E::dim == 1) {
      std::uniform_real_distribution<double> u(-1.0 - margin, 1.0 + margin);
      x[0] = u(rng);
    } else {
      std::uniform_real_distribution<double> u(-margin, 1.0 + margin);
      double s = 0.0;
      for (auto& xi : x) s += (xi = u(rng));
      if (s > 1.0 + margin) continue;
    }
    pts.push_back(x);
  }
  return pts;
}

/// Exponents of all monomials of total degree <= p in dim variables.
std::vector<std::array<int, 3>> monomials(int dim, int p) {
  std::vector<std::array<int, 3>> m;
  for (int a = 0; a <= p; ++a)
    for (int b = 0; b <= (dim >= 2 ? p - a : 0); ++b)
      for (int c = 0; c <= (dim >= 3 ? p - a - b : 0); ++c) m.push_back({a, b, c});
  return m;
}

double ipow(double x, int e) { return e <= 0 ? 1.0 : std::pow(x, e); }

/// Monomial x^e and its first and second derivatives at x.
struct Monomial {
  std::array<int, 3> e;
  double value(const double* x, int dim) const {
    double v = 1.0;
    for (int k = 0; k < dim; ++k) v *= ipow(x[k], e[k]);
    return v;
  }
  double derivative(const double* x, int dim, int i) const {
    if (e[i] == 0) return 0.0;
    double v = e[i] * ipow(x[i], e[i] - 1);
    for (int k = 0; k < dim; ++k)
      if (k != i) v *= ipow(x[k], e[k]);
    return v;
  }
  double second_derivative(const double* x, int dim, int i, int j) const {
    std::array<int, 3> f = e;
    double c = 1.0;
    for (int k : {i, j}) {
      if (f[k] == 0) return 0.0;
      c *= f[k];
      --f[k];
    }
    return c * Monomial{f}.value(x, dim);
  }
};

TYPED_TEST(ShapeFunctionTest, PropertiesAndNodeCoordinatesMatchGmsh) {
  using E = TypeParam;
  const auto g = gmsh_element_properties(E::gmsh_type);
  EXPECT_EQ(g.dim, E::dim);
  EXPECT_EQ(g.order, E::order);
  EXPECT_EQ(g.num_nodes, E::num_nodes);
  EXPECT_EQ(g.num_primary_nodes, E::num_vertices);
  ASSERT_EQ(g.coords.size(), static_cast<std::size_t>(E::num_nodes * E::dim));
  for (int a = 0; a < E::num_nodes; ++a)
    for (int i = 0; i < E::dim; ++i) {
      EXPECT_NEAR(E::nodes()[a][i], g.coords[a * E::dim + i], 1e-15) << "node " << a;
      EXPECT_EQ(E::node_coords[a * E::dim + i], E::nodes()[a][i]);
    }
}

TYPED_TEST(ShapeFunctionTest, KroneckerPropertyAtGmshNodes) {
  using E = TypeParam;
  const auto g = gmsh_element_properties(E::gmsh_type);
  ASSERT_EQ(g.num_nodes, E::num_nodes);
  for (int b = 0; b < E::num_nodes; ++b) {
    double N[E::num_nodes];
    E::eval(&g.coords[b * E::dim], N);
    for (int a = 0; a < E::num_nodes; ++a)
      EXPECT_NEAR(N[a], a == b ? 1.0 : 0.0, 1e-14) << "N_" << a << " at Gmsh node " << b;
  }
}

TYPED_TEST(ShapeFunctionTest, ValuesAndGradientsMatchGmshBasis) {
  using E = TypeParam;
  const auto pts = random_points<E>(25);
  std::vector<double> flat;
  for (const auto& x : pts) flat.insert(flat.end(), x.begin(), x.end());
  const auto gv = gmsh_lagrange_basis(E::gmsh_type, E::dim, flat, false);
  const auto gg = gmsh_lagrange_basis(E::gmsh_type, E::dim, flat, true);
  ASSERT_EQ(gv.size(), pts.size() * E::num_nodes);
  ASSERT_EQ(gg.size(), pts.size() * E::num_nodes * E::dim);
  for (std::size_t q = 0; q < pts.size(); ++q) {
    double N[E::num_nodes], dN[E::num_nodes * E::dim];
    E::eval(pts[q].data(), N);
    E::eval_gradients(pts[q].data(), dN);
    for (int a = 0; a < E::num_nodes; ++a) {
      EXPECT_NEAR(N[a], gv[q * E::num_nodes + a], 1e-12) << "N_" << a << " at point " << q;
      for (int i = 0; i < E::dim; ++i)
        EXPECT_NEAR(dN[a * E::dim + i], gg[(q * E::num_nodes + a) * E::dim + i], 1e-11)
            << "dN_" << a << "/dxi_" << i << " at point " << q;
    }
  }
}

TYPED_TEST(ShapeFunctionTest, PartitionOfUnityAndDerivativesSumToZero) {
  using E = TypeParam;
  for (const auto& x : random_points<E>(50, 0.2)) {
    double N[E::num_nodes], dN[E::num_nodes * E::dim], d2N[E::num_nodes * E::dim * E::dim];
    E::eval(x.data(), N);
    E::eval_gradients(x.data(), dN);
    E::eval_hessians(x.data(), d2N);
    double s = 0.0;
    for (double v : N) s += v;
    EXPECT_NEAR(s, 1.0, 1e-13);
    for (int i = 0; i < E::dim; ++i) {
      double g = 0.0;
      for (int a = 0; a < E::num_nodes; ++a) g += dN[a * E::dim + i];
      EXPECT_NEAR(g, 0.0, 1e-12) << "component " << i;
      for (int j = 0; j < E::dim; ++j) {
        double h = 0.0;
        for (int a = 0; a < E::num_nodes; ++a) h += d2N[(a * E::dim + i) * E::dim + j];
        EXPECT_NEAR(h, 0.0, 1e-11) << "component " << i << j;
      }
    }
  }
}

// Sum_a N_a(xi) p(x_a) = p(xi) for every monomial p of degree <= order, and likewise for
// the first and second derivatives: the element spans the complete polynomial space.
TYPED_TEST(ShapeFunctionTest, ReproducesEveryMonomialUpToItsOrder) {
  using E = TypeParam;
  const auto& X = E::nodes();
  for (const auto& e : monomials(E::dim, E::order)) {
    const Monomial p{e};
    for (const auto& x : random_points<E>(20, 0.2)) {
      double N[E::num_nodes], dN[E::num_nodes * E::dim], d2N[E::num_nodes * E::dim * E::dim];
      E::eval(x.data(), N);
      E::eval_gradients(x.data(), dN);
      E::eval_hessians(x.data(), d2N);
      double v = 0.0;
      std::array<double, E::dim> g{};
      std::array<double, E::dim * E::dim> h{};
      for (int a = 0; a < E::num_nodes; ++a) {
        const double pa = p.value(X[a].data(), E::dim);
        v += N[a] * pa;
        for (int i = 0; i < E::dim; ++i) {
          g[i] += dN[a * E::dim + i] * pa;
          for (int j = 0; j < E::dim; ++j) h[i * E::dim + j] += d2N[(a * E::dim + i) * E::dim + j] * pa;
        }
      }
      const std::string what =
          "monomial exponents " + std::to_string(e[0]) + " " + std::to_string(e[1]) + " " + std::to_string(e[2]);
      EXPECT_NEAR(v, p.value(x.data(), E::dim), 1e-13) << what;
      for (int i = 0; i < E::dim; ++i) {
        EXPECT_NEAR(g[i], p.derivative(x.data(), E::dim, i), 1e-12) << what;
        for (int j = 0; j < E::dim; ++j)
          EXPECT_NEAR(h[i * E::dim + j], p.second_derivative(x.data(), E::dim, i, j), 1e-11) << what;
      }
    }
  }
}

TYPED_TEST(ShapeFunctionTest, GradientsMatchCentralDifferences) {
  using E = TypeParam;
  const double h = 1e-6;
  for (auto x : random_points<E>(30, 0.2)) {
    double dN[E::num_nodes * E::dim];
    E::eval_gradients(x.data(), dN);
    for (int i = 0; i < E::dim; ++i) {
      double Np[E::num_nodes], Nm[E::num_nodes];
      const double xi = x[i];
      x[i] = xi + h;
      E::eval(x.data(), Np);
      x[i] = xi - h;
      E::eval(x.data(), Nm);
      x[i] = xi;
      for (int a = 0; a < E::num_nodes; ++a)
        EXPECT_NEAR(dN[a * E::dim + i], (Np[a] - Nm[a]) / (2 * h), 1e-7) << "dN_" << a << "/dxi_" << i;
    }
  }
}

TYPED_TEST(ShapeFunctionTest, HessiansMatchCentralDifferencesOfGradients) {
  using E = TypeParam;
  const double h = 1e-6;
  for (auto x : random_points<E>(30, 0.2)) {
    double d2N[E::num_nodes * E::dim * E::dim];
    E::eval_hessians(x.data(), d2N);
    for (int j = 0; j < E::dim; ++j) {
      double gp[E::num_nodes * E::dim], gm[E::num_nodes * E::dim];
      const double xj = x[j];
      x[j] = xj + h;
      E::eval_gradients(x.data(), gp);
      x[j] = xj - h;
      E::eval_gradients(x.data(), gm);
      x[j] = xj;
      for (int a = 0; a < E::num_nodes; ++a)
        for (int i = 0; i < E::dim; ++i)
          EXPECT_NEAR(d2N[(a * E::dim + i) * E::dim + j], (gp[a * E::dim + i] - gm[a * E::dim + i]) / (2 * h), 1e-6)
              << "d2N_" << a << "/dxi_" << i << "dxi_" << j;
    }
  }
}

TYPED_TEST(ShapeFunctionTest, EigenHelpersAndFacadeAgreeWithRawFunctions) {
  using E = TypeParam;
  const ReferenceElement& re = reference_element(E::gmsh_type);
  EXPECT_EQ(re.dim, E::dim);
  EXPECT_EQ(re.order, E::order);
  EXPECT_EQ(re.num_nodes, E::num_nodes);
  EXPECT_EQ(re.num_vertices, E::num_vertices);
  for (int a = 0; a < E::num_nodes; ++a)
    for (int i = 0; i < E::dim; ++i) EXPECT_EQ(re.node(a)[i], E::nodes()[a][i]);
  for (const auto& x : random_points<E>(5)) {
    const typename E::Coords xi = Eigen::Map<const typename E::Coords>(x.data());
    const typename E::Values N = E::values(xi);
    const typename E::Gradients dN = E::gradients(xi);
    double Nr[E::num_nodes], dNr[E::num_nodes * E::dim], d2Nr[E::num_nodes * E::dim * E::dim];
    double Nf[E::num_nodes], dNf[E::num_nodes * E::dim], d2Nf[E::num_nodes * E::dim * E::dim];
    E::eval(x.data(), Nr);
    E::eval_gradients(x.data(), dNr);
    E::eval_hessians(x.data(), d2Nr);
    re.eval(x.data(), Nf);
    re.eval_gradients(x.data(), dNf);
    re.eval_hessians(x.data(), d2Nf);
    for (int a = 0; a < E::num_nodes; ++a) {
      EXPECT_EQ(N[a], Nr[a]);
      EXPECT_EQ(Nf[a], Nr[a]);
      for (int i = 0; i < E::dim; ++i) {
        EXPECT_EQ(dN(a, i), dNr[a * E::dim + i]);
        EXPECT_EQ(dNf[a * E::dim + i], dNr[a * E::dim + i]);
        for (int j = 0; j < E::dim; ++j)
          EXPECT_EQ(d2Nf[(a * E::dim + i) * E::dim + j], d2Nr[(a * E::dim + i) * E::dim + j]);
      }
    }
  }
}

// Facets: on edge 0-1 of a Tri10 (xi = t, eta = 0) the shape functions of nodes 0, 1, 3, 4
// are those of a Line4 at s = 2t - 1 and the others vanish; on face z = 0 of a Tet20 the
// nodes 0, 1, 2, 4, 5, 6, 7, 8, 9, 16 carry a Tri10. So Gmsh's facet elements (line4 on a
// tri10 boundary, tri10 on a tet20 boundary) are traces of the cell's functions.
TEST(FacetTraces, Tri10EdgeIsLine4) {
  const std::array<int, 4> on_edge{0, 1, 3, 4};
  for (double t : {0.0, 0.13, 0.5, 0.71, 1.0}) {
    const double xi[2] = {t, 0.0}, s = 2.0 * t - 1.0;
    double N[10], L[4];
    Tri10::eval(xi, N);
    Line4::eval(&s, L);
    for (int a = 0; a < 10; ++a) {
      double expected = 0.0;
      for (int k = 0; k < 4; ++k)
        if (on_edge[k] == a) expected = L[k];
      EXPECT_NEAR(N[a], expected, 1e-14) << "node " << a << " t " << t;
    }
  }
}

TEST(FacetTraces, Tet20FaceIsTri10) {
  const std::array<int, 10> on_face{0, 1, 2, 4, 5, 6, 7, 8, 9, 16};
  for (const auto& x : random_points<Tri10>(10)) {
    const double xi[3] = {x[0], x[1], 0.0};
    double N[20], T[10];
    Tet20::eval(xi, N);
    Tri10::eval(x.data(), T);
    for (int a = 0; a < 20; ++a) {
      double expected = 0.0;
      for (int k = 0; k < 10; ++k)
        if (on_face[k] == a) expected = T[k];
      EXPECT_NEAR(N[a], expected, 1e-14) << "node " << a;
    }
  }
}

}  // namespace
}  // namespace shellflow::fem
