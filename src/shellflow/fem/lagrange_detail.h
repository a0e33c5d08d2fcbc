#pragma once
// Building blocks of the Lagrange elements in shape_functions.h: the reference simplices
// (barycentric coordinates and their constant derivatives) and the shape function of one
// node written in barycentric coordinates. Everything is resolved at compile time so that
// an element's eval() inlines to straight-line arithmetic with no tables or branches.
#include <array>

namespace shellflow::fem::detail {

/// Where a Lagrange node of an order-p simplex element sits.
enum class NodeKind { vertex, edge, face };

/// One node of a Lagrange simplex element: a vertex `a`; an edge node on edge (a, b) closer
/// to `a` than to `b` (for order 2 the midpoint, where the direction is irrelevant); or the
/// face node of the triangle (a, b, c) (order 3 only). Used as a template argument.
struct NodeSpec {
  NodeKind kind;
  int a;
  int b;
  int c;
};
constexpr NodeSpec vertex(int a) { return {NodeKind::vertex, a, -1, -1}; }
constexpr NodeSpec edge(int near, int far) { return {NodeKind::edge, near, far, -1}; }
constexpr NodeSpec face(int a, int b, int c) { return {NodeKind::face, a, b, c}; }

// --- reference simplices --------------------------------------------------------------------
// Each provides the barycentric coordinates L[0..dim] of a point xi, the vertex coordinates,
// and the chain rule from derivatives with respect to the L's (treated as independent) to
// derivatives with respect to xi. The L-derivatives arrive in local arrays whose zero
// entries the compiler knows, so each output is written once with only the needed work.

/// Gmsh's reference line [-1, 1]: L0 = (1 - xi)/2 at xi = -1, L1 = (1 + xi)/2 at xi = +1.
struct LineSimplex {
  static constexpr int dim = 1;
  static constexpr std::array<std::array<double, 1>, 2> vertices{{{-1.0}, {1.0}}};
  static void lambdas(const double* xi, double* L) {
    L[0] = 0.5 * (1.0 - xi[0]);
    L[1] = 0.5 * (1.0 + xi[0]);
  }
  /// g = sum_m P[m] dL_m/dxi.
  static void chain_gradient(const std::array<double, 2>& P, double* g) { g[0] = 0.5 * (P[1] - P[0]); }
  /// h = sum_mn H[m][n] dL_m/dxi dL_n/dxi.
  static void chain_hessian(const std::array<std::array<double, 2>, 2>& H, double* h) {
    h[0] = 0.25 * ((H[1][1] - H[0][1]) - (H[1][0] - H[0][0]));
  }
};

/// Unit simplex of dimension D (Gmsh's triangle for D = 2, tetrahedron for D = 3):
/// L0 = 1 - sum(xi), L_{k+1} = xi_k, so dL0/dxi = (-1, ..., -1) and dL_{k+1}/dxi = e_k.
template <int D>
struct UnitSimplex {
  static constexpr int dim = D;
  static constexpr std::array<std::array<double, D>, D + 1> vertices = [] {
    std::array<std::array<double, D>, D + 1> v{};
    for (int k = 0; k < D; ++k) v[k + 1][k] = 1.0;
    return v;
  }();
  static void lambdas(const double* xi, double* L) {
    double s = 0.0;
    for (int k = 0; k < D; ++k) {
      L[k + 1] = xi[k];
      s += xi[k];
    }
    L[0] = 1.0 - s;
  }
  static void chain_gradient(const std::array<double, D + 1>& P, double* g) {
    for (int k = 0; k < D; ++k) g[k] = P[k + 1] - P[0];
  }
  /// h is D x D row-major.
  static void chain_hessian(const std::array<std::array<double, D + 1>, D + 1>& H, double* h) {
    for (int k = 0; k < D; ++k)
      for (int l = 0; l < D; ++l) h[k * D + l] = (H[k + 1][l + 1] - H[0][l + 1]) - (H[k + 1][0] - H[0][0]);
  }
};

// --- one node's shape function, order 1 to 3 --------------------------------------------
// Order 1: vertex L.
// Order 2: vertex L(2L - 1); edge 4 La Lb.
// Order 3: vertex L(3L - 1)(3L - 2)/2; edge (near a) 9/2 La Lb (3La - 1); face 27 La Lb Lc.

template <int P, NodeSpec S>
inline double node_value(const double* L) {
  if constexpr (S.kind == NodeKind::vertex) {
    const double l = L[S.a];
    if constexpr (P == 1) return l;
    if constexpr (P == 2) return l * (2.0 * l - 1.0);
    if constexpr (P == 3) return 0.5 * l * (3.0 * l - 1.0) * (3.0 * l - 2.0);
  } else if constexpr (S.kind == NodeKind::edge) {
    static_assert(P == 2 || P == 3);
    if constexpr (P == 2) return 4.0 * L[S.a] * L[S.b];
    if constexpr (P == 3) return 4.5 * L[S.a] * L[S.b] * (3.0 * L[S.a] - 1.0);
  } else {
    static_assert(P == 3);
    return 27.0 * L[S.a] * L[S.b] * L[S.c];
  }
}

/// dN/dxi of the node into g[0..dim).
template <class Simplex, int P, NodeSpec S>
inline void node_gradient(const double* L, double* g) {
  std::array<double, Simplex::dim + 1> d{};  // dN/dL_m
  if constexpr (S.kind == NodeKind::vertex) {
    const double l = L[S.a];
    if constexpr (P == 1) d[S.a] = 1.0;
    if constexpr (P == 2) d[S.a] = 4.0 * l - 1.0;
    if constexpr (P == 3) d[S.a] = (13.5 * l - 9.0) * l + 1.0;
  } else if constexpr (S.kind == NodeKind::edge) {
    const double la = L[S.a], lb = L[S.b];
    if constexpr (P == 2) {
      d[S.a] = 4.0 * lb;
      d[S.b] = 4.0 * la;
    } else {
      d[S.a] = 4.5 * lb * (6.0 * la - 1.0);
      d[S.b] = 4.5 * la * (3.0 * la - 1.0);
    }
  } else {
    const double la = L[S.a], lb = L[S.b], lc = L[S.c];
    d[S.a] = 27.0 * lb * lc;
    d[S.b] = 27.0 * la * lc;
    d[S.c] = 27.0 * la * lb;
  }
  Simplex::chain_gradient(d, g);
}

/// d2N/dxi2 of the node into h (dim x dim row-major).
template <class Simplex, int P, NodeSpec S>
inline void node_hessian(const double* L, double* h) {
  std::array<std::array<double, Simplex::dim + 1>, Simplex::dim + 1> d{};  // d2N/dL_m dL_n
  if constexpr (P == 1) {
    (void)L;
  } else if constexpr (S.kind == NodeKind::vertex) {
    d[S.a][S.a] = P == 2 ? 4.0 : 27.0 * L[S.a] - 9.0;
  } else if constexpr (S.kind == NodeKind::edge) {
    if constexpr (P == 2) {
      d[S.a][S.b] = d[S.b][S.a] = 4.0;
    } else {
      d[S.a][S.a] = 27.0 * L[S.b];
      d[S.a][S.b] = d[S.b][S.a] = 4.5 * (6.0 * L[S.a] - 1.0);
    }
  } else {
    d[S.a][S.b] = d[S.b][S.a] = 27.0 * L[S.c];
    d[S.a][S.c] = d[S.c][S.a] = 27.0 * L[S.b];
    d[S.b][S.c] = d[S.c][S.b] = 27.0 * L[S.a];
  }
  Simplex::chain_hessian(d, h);
}

/// Reference coordinates of a node: the vertex, the point at 1/P of edge (a, b) from a,
/// or the face centroid.
template <class Simplex, int P>
constexpr std::array<double, Simplex::dim> node_position(NodeSpec s) {
  std::array<double, Simplex::dim> x{};
  const auto& v = Simplex::vertices;
  for (int k = 0; k < Simplex::dim; ++k) {
    switch (s.kind) {
      case NodeKind::vertex:
        x[k] = v[s.a][k];
        break;
      case NodeKind::edge:
        x[k] = ((P - 1) * v[s.a][k] + v[s.b][k]) / P;
        break;
      case NodeKind::face:
        x[k] = (v[s.a][k] + v[s.b][k] + v[s.c][k]) / 3.0;
        break;
    }
  }
  return x;
}

}  // namespace shellflow::fem::detail
