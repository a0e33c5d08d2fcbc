#pragma once
// Structured unit-cube meshes for the benchmarks: the tests' box (tests/support/box_mesh.h)
// of n^3 cubes with boundary groups "inflow" (x = 0), "outflow" (x = 1), "walls" (y = 0, 1)
// and "symmetry" (z = 0, 1).
#include <cmath>
#include <string>

#include "support/box_mesh.h"

namespace shellflow::fluid::bench {

inline mesh::Mesh box_mesh(int n) {
  return support::box_mesh({n, n, n}, Vec3(1, 1, 1), [](const Vec3& c) -> std::string {
    constexpr double tol = 1e-12;
    if (std::abs(c.x()) < tol) return "inflow";
    if (std::abs(c.x() - 1.0) < tol) return "outflow";
    if (std::abs(c.y()) < tol || std::abs(c.y() - 1.0) < tol) return "walls";
    return "symmetry";
  });
}

}  // namespace shellflow::fluid::bench
