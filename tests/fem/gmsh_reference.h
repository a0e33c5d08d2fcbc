#pragma once
// Reference data straight from the Gmsh library, so that tests compare shellflow's element
// definitions with Gmsh's own instead of with numbers typed into the tests.
#include <gmsh.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace shellflow::fem::testing {

/// Keeps Gmsh initialised for the whole test program (registered in gmsh_reference.cpp).
class GmshEnvironment : public ::testing::Environment {
 public:
  void SetUp() override {
    gmsh::initialize();
    gmsh::option::setNumber("General.Terminal", 0);
  }
  void TearDown() override { gmsh::finalize(); }
};

struct GmshElementProperties {
  std::string name;
  int dim = 0;
  int order = 0;
  int num_nodes = 0;
  int num_primary_nodes = 0;
  std::vector<double> coords;  ///< num_nodes x dim
};

inline GmshElementProperties gmsh_element_properties(int gmsh_type) {
  GmshElementProperties p;
  gmsh::model::mesh::getElementProperties(gmsh_type, p.name, p.dim, p.order, p.num_nodes, p.coords,
                                          p.num_primary_nodes);
  return p;
}

/// Gmsh's Lagrange basis at points given as `dim` coordinates each: values (npoints x
/// num_nodes) or, with gradients = true, gradients (npoints x num_nodes x dim).
inline std::vector<double> gmsh_lagrange_basis(int gmsh_type, int dim, const std::vector<double>& points,
                                               bool gradients) {
  std::vector<double> uvw;
  const std::size_t np = points.size() / static_cast<std::size_t>(dim);
  for (std::size_t q = 0; q < np; ++q)
    for (int k = 0; k < 3; ++k) uvw.push_back(k < dim ? points[q * dim + k] : 0.0);
  int num_components = 0, num_orientations = 0;
  std::vector<double> basis;
  gmsh::model::mesh::getBasisFunctions(gmsh_type, uvw, gradients ? "GradLagrange" : "Lagrange", num_components, basis,
                                       num_orientations);
  if (!gradients) return basis;
  // Gmsh always returns 3 components; keep the first dim.
  std::vector<double> g;
  for (std::size_t i = 0; i < basis.size() / 3; ++i)
    for (int k = 0; k < dim; ++k) g.push_back(basis[3 * i + k]);
  return g;
}

}  // namespace shellflow::fem::testing
