#pragma once
// Runtime facade over the element classes of shape_functions.h, looked up by Gmsh element
// type number, for generic code (mesh readers, output, tests). Hot loops should dispatch
// once with visit_element_type() and then call the element class directly.
#include <span>
#include <stdexcept>

#include "shellflow/core/error.h"
#include "shellflow/fem/shape_functions.h"

namespace shellflow::fem {

/// Everything generic code needs about one element type. Instances are static and
/// immutable; compare them by address or by gmsh_type.
struct ReferenceElement {
  int gmsh_type;
  const char* name;  ///< "Tri10", "Tet20", ...
  int dim;
  int order;
  int num_nodes;
  int num_vertices;
  /// Same conventions as the element classes (shape_functions.h).
  void (*eval)(const double* xi, double* N);
  void (*eval_gradients)(const double* xi, double* dN);
  void (*eval_hessians)(const double* xi, double* d2N);
  /// Node coordinates, num_nodes x dim row-major.
  const double* node_coords;

  std::span<const double> node(int a) const {
    return {node_coords + static_cast<std::ptrdiff_t>(a) * dim, static_cast<std::size_t>(dim)};
  }
  std::span<const double> nodes() const {
    return {node_coords, static_cast<std::size_t>(num_nodes) * static_cast<std::size_t>(dim)};
  }
};

/// The facade of element class E.
template <class E>
constexpr ReferenceElement make_reference_element(const char* name) {
  return {E::gmsh_type,
          name,
          E::dim,
          E::order,
          E::num_nodes,
          E::num_vertices,
          &E::eval,
          &E::eval_gradients,
          &E::eval_hessians,
          E::node_coords.data()};
}

/// Gmsh type numbers of every element type handled: 1, 8, 26 (lines), 2, 9, 21
/// (triangles), 4, 11, 29 (tetrahedra).
std::span<const int> supported_gmsh_types();

/// nullptr when the type is not handled.
const ReferenceElement* find_reference_element(int gmsh_type) noexcept;

/// Throws InputError naming the type and the supported ones when it is not handled.
const ReferenceElement& reference_element(int gmsh_type);

/// Calls f(E{}) with the element class E of the Gmsh type, so generic code can switch to
/// compile-time sizes once per element block. Throws InputError for an unhandled type.
template <class F>
decltype(auto) visit_element_type(int gmsh_type, F&& f) {
  switch (gmsh_type) {
    case Line2::gmsh_type:
      return std::forward<F>(f)(Line2{});
    case Line3::gmsh_type:
      return std::forward<F>(f)(Line3{});
    case Line4::gmsh_type:
      return std::forward<F>(f)(Line4{});
    case Tri3::gmsh_type:
      return std::forward<F>(f)(Tri3{});
    case Tri6::gmsh_type:
      return std::forward<F>(f)(Tri6{});
    case Tri10::gmsh_type:
      return std::forward<F>(f)(Tri10{});
    case Tet4::gmsh_type:
      return std::forward<F>(f)(Tet4{});
    case Tet10::gmsh_type:
      return std::forward<F>(f)(Tet10{});
    case Tet20::gmsh_type:
      return std::forward<F>(f)(Tet20{});
    default:
      break;
  }
  (void)reference_element(gmsh_type);  // throws the descriptive error
  throw std::logic_error("unreachable");
}

}  // namespace shellflow::fem
