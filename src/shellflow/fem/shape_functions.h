#pragma once
// Lagrange shape functions of the line, triangle and tetrahedron elements shellflow uses,
// in Gmsh's node ordering and on Gmsh's reference elements:
//   line        [-1, 1]                          (Gmsh types 1, 8, 26: Line2, Line3, Line4)
//   triangle    (0,0) (1,0) (0,1)                (types 2, 9, 21: Tri3, Tri6, Tri10)
//   tetrahedron (0,0,0) (1,0,0) (0,1,0) (0,0,1)  (types 4, 11, 29: Tet4, Tet10, Tet20)
// Each element is a class with compile-time sizes and static, inlinable functions for hot
// loops; ReferenceElement (reference_element.h) is the runtime-dispatch facade over them.
//
// Conventions of the raw-pointer functions (xi has `dim` entries):
//   eval(xi, N)             N[a]                       = N_a(xi)
//   eval_gradients(xi, dN)  dN[a*dim + i]              = dN_a/dxi_i
//   eval_hessians(xi, d2N)  d2N[(a*dim + i)*dim + j]   = d2N_a/dxi_i dxi_j
// The formulas are polynomials: they may be evaluated outside the element (a locator's
// Newton iterations do so).
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <utility>

#include "shellflow/fem/lagrange_detail.h"

namespace shellflow::fem {

/// A Lagrange element of order `Order` on `Simplex`, with nodes `Nodes` listed in Gmsh's
/// order. The concrete elements below derive from it.
template <class Simplex, int Order, int GmshType, std::size_t NumNodes,
          const std::array<detail::NodeSpec, NumNodes>& Nodes>
struct LagrangeElement {
  static constexpr int dim = Simplex::dim;
  static constexpr int order = Order;
  static constexpr int num_nodes = static_cast<int>(NumNodes);
  static constexpr int num_vertices = dim + 1;
  static constexpr int gmsh_type = GmshType;

  using Point = std::array<double, dim>;
  /// Reference coordinates (Eigen view of xi).
  using Coords = Eigen::Matrix<double, dim, 1>;
  using Values = Eigen::Matrix<double, num_nodes, 1>;
  /// num_nodes x dim, rows are gradients; row-major so its data matches eval_gradients.
  using Gradients = Eigen::Matrix<double, num_nodes, dim, (dim == 1 ? Eigen::ColMajor : Eigen::RowMajor)>;

  /// Node coordinates in the reference element, one point per node.
  static constexpr std::array<Point, NumNodes> node_points = [] {
    std::array<Point, NumNodes> x{};
    for (std::size_t a = 0; a < NumNodes; ++a) x[a] = detail::node_position<Simplex, Order>(Nodes[a]);
    return x;
  }();
  /// The same, flat: node a's coordinate i is node_coords[a*dim + i].
  static constexpr std::array<double, NumNodes* dim> node_coords = [] {
    std::array<double, NumNodes * dim> x{};
    for (std::size_t a = 0; a < NumNodes; ++a)
      for (int i = 0; i < dim; ++i) x[a * dim + i] = node_points[a][i];
    return x;
  }();
  static const std::array<Point, NumNodes>& nodes() { return node_points; }

  static void eval(const double* xi, double* N) {
    double L[dim + 1];
    Simplex::lambdas(xi, L);
    eval_impl(L, N, std::make_index_sequence<NumNodes>{});
  }

  static void eval_gradients(const double* xi, double* dN) {
    double L[dim + 1];
    Simplex::lambdas(xi, L);
    gradients_impl(L, dN, std::make_index_sequence<NumNodes>{});
  }

  static void eval_hessians(const double* xi, double* d2N) {
    double L[dim + 1];
    Simplex::lambdas(xi, L);
    hessians_impl(L, d2N, std::make_index_sequence<NumNodes>{});
  }

  // Eigen-friendly forms of the same.
  static Values values(const Coords& xi) {
    Values N;
    eval(xi.data(), N.data());
    return N;
  }
  static Gradients gradients(const Coords& xi) {
    Gradients dN;
    eval_gradients(xi.data(), dN.data());
    return dN;
  }

 private:
  template <std::size_t... A>
  static void eval_impl(const double* L, double* N, std::index_sequence<A...>) {
    ((N[A] = detail::node_value<Order, Nodes[A]>(L)), ...);
  }
  template <std::size_t... A>
  static void gradients_impl(const double* L, double* dN, std::index_sequence<A...>) {
    (detail::node_gradient<Simplex, Order, Nodes[A]>(L, dN + A * dim), ...);
  }
  template <std::size_t... A>
  static void hessians_impl(const double* L, double* d2N, std::index_sequence<A...>) {
    (detail::node_hessian<Simplex, Order, Nodes[A]>(L, d2N + A * dim * dim), ...);
  }
};

// --- Gmsh node orderings -----------------------------------------------------------------
// Vertices first, then edge nodes edge by edge, each edge's nodes running from its first
// vertex to its second, then face nodes. The tables are read off Gmsh
// (gmsh::model::mesh::getElementProperties) and checked against it by the tests.
namespace detail {
inline constexpr std::array<NodeSpec, 2> line2_nodes{vertex(0), vertex(1)};
inline constexpr std::array<NodeSpec, 3> line3_nodes{vertex(0), vertex(1), edge(0, 1)};
inline constexpr std::array<NodeSpec, 4> line4_nodes{vertex(0), vertex(1), edge(0, 1), edge(1, 0)};

inline constexpr std::array<NodeSpec, 3> tri3_nodes{vertex(0), vertex(1), vertex(2)};
// Edges 0-1, 1-2, 2-0.
inline constexpr std::array<NodeSpec, 6> tri6_nodes{vertex(0),  vertex(1),  vertex(2),
                                                    edge(0, 1), edge(1, 2), edge(2, 0)};
inline constexpr std::array<NodeSpec, 10> tri10_nodes{vertex(0),    vertex(1),  vertex(2),  //
                                                      edge(0, 1),   edge(1, 0), edge(1, 2),
                                                      edge(2, 1),   edge(2, 0), edge(0, 2),  //
                                                      face(0, 1, 2)};

inline constexpr std::array<NodeSpec, 4> tet4_nodes{vertex(0), vertex(1), vertex(2), vertex(3)};
// Edges 0-1, 1-2, 2-0, 3-0, 3-2, 3-1 (note: not VTK's 0-1, 1-2, 2-0, 0-3, 1-3, 2-3).
inline constexpr std::array<NodeSpec, 10> tet10_nodes{vertex(0),  vertex(1),  vertex(2),  vertex(3),  //
                                                      edge(0, 1), edge(1, 2), edge(2, 0), edge(3, 0),
                                                      edge(3, 2), edge(3, 1)};
// Same edges, two nodes each from the first vertex to the second; then one node per face,
// faces (0,1,2), (0,1,3), (0,2,3), (1,2,3).
inline constexpr std::array<NodeSpec, 20> tet20_nodes{vertex(0),     vertex(1),     vertex(2),     vertex(3),   //
                                                      edge(0, 1),    edge(1, 0),    edge(1, 2),    edge(2, 1),  //
                                                      edge(2, 0),    edge(0, 2),    edge(3, 0),    edge(0, 3),  //
                                                      edge(3, 2),    edge(2, 3),    edge(3, 1),    edge(1, 3),  //
                                                      face(0, 1, 2), face(0, 1, 3), face(0, 2, 3), face(1, 2, 3)};
}  // namespace detail

// --- the elements ------------------------------------------------------------------------
// Lines live on [-1, 1] as in Gmsh (so a Tri10 edge of parameter t in [0, 1] has
// xi = 2t - 1 on its Line4).

struct Line2 : LagrangeElement<detail::LineSimplex, 1, 1, 2, detail::line2_nodes> {};
struct Line3 : LagrangeElement<detail::LineSimplex, 2, 8, 3, detail::line3_nodes> {};
struct Line4 : LagrangeElement<detail::LineSimplex, 3, 26, 4, detail::line4_nodes> {};

struct Tri3 : LagrangeElement<detail::UnitSimplex<2>, 1, 2, 3, detail::tri3_nodes> {};
struct Tri6 : LagrangeElement<detail::UnitSimplex<2>, 2, 9, 6, detail::tri6_nodes> {};
struct Tri10 : LagrangeElement<detail::UnitSimplex<2>, 3, 21, 10, detail::tri10_nodes> {};

struct Tet4 : LagrangeElement<detail::UnitSimplex<3>, 1, 4, 4, detail::tet4_nodes> {};
struct Tet10 : LagrangeElement<detail::UnitSimplex<3>, 2, 11, 10, detail::tet10_nodes> {};
struct Tet20 : LagrangeElement<detail::UnitSimplex<3>, 3, 29, 20, detail::tet20_nodes> {};

}  // namespace shellflow::fem
