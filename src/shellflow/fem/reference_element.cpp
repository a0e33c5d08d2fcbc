#include "shellflow/fem/reference_element.h"

#include <array>
#include <string>

namespace shellflow::fem {
namespace {

constexpr std::array<ReferenceElement, 9> kElements{
    make_reference_element<Line2>("Line2"), make_reference_element<Line3>("Line3"),
    make_reference_element<Line4>("Line4"), make_reference_element<Tri3>("Tri3"),
    make_reference_element<Tri6>("Tri6"),   make_reference_element<Tri10>("Tri10"),
    make_reference_element<Tet4>("Tet4"),   make_reference_element<Tet10>("Tet10"),
    make_reference_element<Tet20>("Tet20"),
};

constexpr std::array<int, 9> kTypes = [] {
  std::array<int, 9> t{};
  for (std::size_t i = 0; i < kElements.size(); ++i) t[i] = kElements[i].gmsh_type;
  return t;
}();

}  // namespace

std::span<const int> supported_gmsh_types() { return kTypes; }

const ReferenceElement* find_reference_element(int gmsh_type) noexcept {
  for (const auto& e : kElements)
    if (e.gmsh_type == gmsh_type) return &e;
  return nullptr;
}

const ReferenceElement& reference_element(int gmsh_type) {
  if (const auto* e = find_reference_element(gmsh_type)) return *e;
  std::string known;
  for (const auto& e : kElements) known += fmt::format(" {} ({})", e.gmsh_type, e.name);
  throw_input_error(
      "unsupported Gmsh element type {}: shellflow handles{}; mesh with Mesh.ElementOrder "
      "1-3 and without Recombine (no quadrilaterals or hexahedra)",
      gmsh_type, known);
}

}  // namespace shellflow::fem
