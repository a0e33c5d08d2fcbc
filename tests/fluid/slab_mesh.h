#pragma once
// A one-layer slab [0, lx] x [0, ly] x [0, dz] of nx x ny hexahedra, each split into 6
// tetrahedra around its main diagonal (Kuhn), like the panel-flutter slab: every node lies
// on one of the symmetry planes z = 0, dz. Groups "left" (x = 0), "right" (x = lx),
// "bottom" (y = 0), "top" (y = ly), "symmetry" (z = 0 and z = dz).
#include <cmath>
#include <string>

#include "support/box_mesh.h"

namespace shellflow::fluid::test_support {

using shellflow::support::box_mesh;

inline mesh::Mesh slab_mesh(int nx, int ny, double lx, double ly, double dz) {
  mesh::Mesh m = box_mesh({nx, ny, 1}, Vec3(lx, ly, dz), [&](const Vec3& c) -> std::string {
    const double tol = 1e-12 * (lx + ly + dz);
    if (std::abs(c.x()) < tol) return "left";
    if (std::abs(c.x() - lx) < tol) return "right";
    if (std::abs(c.y()) < tol) return "bottom";
    if (std::abs(c.y() - ly) < tol) return "top";
    return "symmetry";
  });
  m.name = "slab";
  return m;
}

}  // namespace shellflow::fluid::test_support
