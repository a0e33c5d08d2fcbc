// mesh/surface_fields.h: the directional wavenumber of a nodal field against sin(k x) on
// flat, tilted and curved strips, and the facets' extent along a direction.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "shellflow/core/error.h"
#include "shellflow/fem/shape_functions.h"
#include "shellflow/mesh/surface_fields.h"

using shellflow::Index;
using shellflow::Vec3;
using namespace shellflow::mesh;

namespace {

constexpr double pi = std::numbers::pi;

/// A strip [0, length] x [0, width] of nx x 1 squares, each cut into two triangles of the
/// element type E; every triangle has its own nodes (the integrals are element-wise), placed
/// by `map` from the plane (x, y).
template <class E>
Mesh strip(int nx, double length, double width, const std::function<Vec3(double, double)>& map) {
  Mesh m;
  m.name = m.source = "strip";
  m.cells.type = static_cast<ElementType>(E::gmsh_type);
  const double h = length / nx;
  for (int i = 0; i < nx; ++i) {
    const Vec3 p0(i * h, 0, 0), p1((i + 1) * h, 0, 0), p2((i + 1) * h, width, 0), p3(i * h, width, 0);
    for (const auto& [a, b, c] : {std::array{p0, p1, p2}, std::array{p0, p2, p3}}) {
      for (const auto& xi : E::node_points) {
        const Vec3 p = a + xi[0] * (b - a) + xi[1] * (c - a);
        m.cells.connectivity.push_back(m.num_nodes());
        m.nodes.push_back(map(p.x(), p.y()));
      }
    }
  }
  return m;
}

Vec3 flat(double x, double y) { return {x, y, 0.0}; }

/// sin(k x) at the nodes, x the first coordinate of the plane point (here: the node's own x).
std::vector<double> sine(const Mesh& m, double k) {
  std::vector<double> f;
  for (const Vec3& p : m.nodes) f.push_back(std::sin(k * p.x()));
  return f;
}

}  // namespace

TEST(SurfaceFields, WavenumberOfASineOnCubicTrianglesAtEightCellsPerWavelength) {
  // Two wavelengths on 16 squares: 8 squares per wavelength.
  const double length = 1.0, k = 2 * 2 * pi / length;
  const Mesh m = strip<shellflow::fem::Tri10>(16, length, 0.1, flat);
  EXPECT_NEAR(directional_wavenumber(m, sine(m, k), Vec3::UnitX()) / k, 1.0, 2e-4);
  // Across the stripes the field does not change.
  EXPECT_NEAR(directional_wavenumber(m, sine(m, k), Vec3::UnitY()), 0.0, 1e-9 * k);
  // An oblique direction sees cos(a) of it; the direction need not be a unit vector.
  const double a = 0.6;
  EXPECT_NEAR(directional_wavenumber(m, sine(m, k), 3.0 * Vec3(std::cos(a), std::sin(a), 0)) / (k * std::cos(a)), 1.0,
              2e-4);
}

TEST(SurfaceFields, WavenumberOnLinearTrianglesConvergesAtSecondOrder) {
  const double length = 1.0, k = 2 * 2 * pi / length;
  double errors[2];
  for (int level = 0; level < 2; ++level) {
    const Mesh m = strip<shellflow::fem::Tri3>(16 << level, length, 0.1, flat);
    errors[level] = std::abs(directional_wavenumber(m, sine(m, k), Vec3::UnitX()) / k - 1.0);
  }
  EXPECT_GT(errors[0], 1e-3);  // visible at 8 cells per wavelength
  EXPECT_NEAR(std::log2(errors[0] / errors[1]), 2.0, 0.1);
}

TEST(SurfaceFields, WavenumberUsesTheSurfaceGradientOnTiltedAndCurvedSurfaces) {
  const double length = 1.0, k = 2 * 2 * pi / length;
  // The strip tilted about x by 40 degrees: x stays tangent; z is normal to it in part.
  const double t = 40 * pi / 180;
  const auto tilted = [&](double x, double y) { return Vec3(x, y * std::cos(t), y * std::sin(t)); };
  const Mesh tilt = strip<shellflow::fem::Tri10>(16, length, 0.1, tilted);
  EXPECT_NEAR(directional_wavenumber(tilt, sine(tilt, k), Vec3::UnitX()) / k, 1.0, 2e-4);
  // A direction out of the flat strip's plane: only its tangent part, cos(a) x, counts.
  const double a = 0.5;
  const Mesh m = strip<shellflow::fem::Tri10>(16, length, 0.1, flat);
  EXPECT_NEAR(directional_wavenumber(m, sine(m, k), Vec3(std::cos(a), 0, std::sin(a))) / (k * std::cos(a)), 1.0, 2e-4);
  // A cylinder of radius R with its axis along x, the strip wrapped around it: x is a
  // tangent of unit length everywhere, so the wavenumber along x is k.
  const double R = 0.2;
  const auto cylinder = [&](double x, double y) { return Vec3(x, R * std::sin(y / R), R * (1 - std::cos(y / R))); };
  const Mesh curved = strip<shellflow::fem::Tri10>(16, length, 0.3, cylinder);
  EXPECT_NEAR(directional_wavenumber(curved, sine(curved, k), Vec3::UnitX()) / k, 1.0, 2e-4);
}

TEST(SurfaceFields, ExtentAlongADirectionIsTheStripSpacing) {
  const Mesh m = strip<shellflow::fem::Tri3>(10, 1.0, 0.4, flat);
  EXPECT_NEAR(mean_extent(m, m.cells, Vec3::UnitX()), 0.1, 1e-14);
  EXPECT_NEAR(mean_extent(m, m.cells, Vec3::UnitY()), 0.4, 1e-14);
  EXPECT_NEAR(mean_extent(m, m.cells, Vec3::UnitZ()), 0.0, 1e-14);
  EXPECT_EQ(mean_extent(m, ElementBlock{}, Vec3::UnitX()), 0.0);
}

TEST(SurfaceFields, WavenumberRefusesAZeroFieldAndAWrongSize) {
  const Mesh m = strip<shellflow::fem::Tri3>(4, 1.0, 0.1, flat);
  EXPECT_THROW(directional_wavenumber(m, std::vector<double>(m.nodes.size(), 0.0), Vec3::UnitX()),
               shellflow::InputError);
  EXPECT_THROW(directional_wavenumber(m, std::vector<double>(3, 1.0), Vec3::UnitX()), shellflow::InputError);
}
