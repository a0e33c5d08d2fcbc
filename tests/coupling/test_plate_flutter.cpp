// Linear flutter of 3-D plates and a shallow cylindrical panel (docs/flutter.md, "3-D
// panels") against an independent model written for the tests: Rayleigh-Ritz on tensor
// products of beam eigenfunctions (sines, clamped-clamped beam functions), Donnell's shallow
// shell with the in-plane fields condensed, first-order piston theory, mu/M -> 0
// (plate_flutter_reference.h, whose own tests are test_plate_flutter_reference.cpp). Both fix
// the edges' positions completely (shellflow's `simply_supported` and `clamped`).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "../shell/structured_shell_mesh.h"
#include "coupling_test_util.h"
#include "plate_flutter_reference.h"
#include "shellflow/coupling/linear_flutter.h"
#include "shellflow/coupling/piston_theory.h"

namespace shellflow::coupling {
namespace {

namespace ref = shellflow::testing::plate_reference;

constexpr double h = 1.35e-3, E = 77.28e9, nu = 0.33, rho_m = 2710.0;

struct PlateCase {
  const char* name;
  double a, b;    // streamwise length (x), span (y)
  double radius;  // of the cylinder about an axis along x; 0: flat
  bool clamped;
  int nx, ny;  // cubic elements
};

/// The plate in the plane z = 0 (curved: z = the cylinder's height above its edges), flow
/// along +x, wet side +z; every edge clamped or simply supported.
shell::ShellModel plate(const PlateCase& c) {
  const double R = c.radius, half = 0.5 * c.b;
  mesh::Mesh m = shell::testing::structured_shell_mesh(c.a, c.b, c.nx, c.ny, [&](double s, double t) {
    if (R == 0.0) return Vec3(s, t - half, 0.0);
    const double phi = std::asin(half / R) * (t - half) / half;  // the arc through the chord's ends
    return Vec3(s, R * std::sin(phi), R * std::cos(phi) - std::sqrt(R * R - half * half));
  });
  shell::ShellSection section;
  section.thickness = h;
  section.material = {E, nu, rho_m};
  shell::ShellModel model(std::move(m), section);
  for (const char* g : {"left", "right", "bottom", "top"})
    model.add_support(c.clamped ? shell::Support::clamped(g) : shell::Support::simply_supported(g));
  return model;
}

ref::Flutter reference(const PlateCase& c) {
  ref::Plate p;
  p.a = c.a;
  p.b = c.b;
  p.h = h;
  p.E = E;
  p.nu = nu;
  p.rho = rho_m;
  if (c.radius > 0.0) p.R = c.radius;
  p.x_edges = p.y_edges = c.clamped ? ref::Edge::clamped : ref::Edge::simply_supported;
  // Mode counts converged to ~1e-4 (test_plate_flutter_reference.cpp's tables).
  p.modes_x = 12;
  p.modes_y = c.clamped ? 9 : (c.radius > 0.0 ? 5 : 1);
  return ref::critical_lambda(p);
}

struct Critical {
  double lambda, frequency_hz;
};

Critical shellflow_critical(const PlateCase& c, int modes) {
  const shell::ShellModel model = plate(c);
  PistonTheoryFlow flow;
  flow.density = 0.339;
  flow.mach = 3.0;
  flow.speed = 3.0 * std::sqrt(1.4 * 28000.0 / 0.339);
  flow.direction = Vec3::UnitX();
  flow.wet_normal = Vec3::UnitZ();
  const PistonTheory theory(model, flow);
  const LinearFlutterSystem linear(model, modes);
  const auto r =
      sweep_flutter(linear, PistonAerodynamics(linear, theory), coupling_test::panel_flutter_setting(c.a, 3.0, false),
                    FlutterParameter::lambda, 0.0, 2000.0, 21);
  EXPECT_TRUE(r.critical) << c.name;
  return r.critical ? Critical{r.critical->lambda, r.critical->frequency_hz} : Critical{NAN, NAN};
}

TEST(PlateFlutter, SquareRectangleAndCylindricalPanelMeetTheRitzModel) {
  const double R = 0.25 / (5.0 * h);  // a^2 / (R h) = 5
  const PlateCase cases[] = {
      {"simply supported square", 0.5, 0.5, 0.0, false, 12, 12},
      {"clamped square", 0.5, 0.5, 0.0, true, 12, 12},
      {"simply supported 2:1", 0.5, 0.25, 0.0, false, 12, 6},
      {"cylindrical, a^2/(R h) = 5", 0.5, 0.5, R, false, 12, 12},
  };
  std::printf("%-28s %12s %12s %8s %10s %10s\n", "case", "lambda_cr", "Ritz", "error", "f_cr [Hz]", "Ritz");
  double flat = 0.0, flat_ref = 0.0;
  for (const PlateCase& c : cases) {
    const Critical s = shellflow_critical(c, 32);
    const ref::Flutter r = reference(c);
    std::printf("%-28s %12.3f %12.3f %7.3f%% %10.3f %10.3f\n", c.name, s.lambda, r.lambda_cr,
                100.0 * (s.lambda / r.lambda_cr - 1.0), s.frequency_hz, r.frequency_hz);
    EXPECT_NEAR(s.lambda, r.lambda_cr, 0.01 * r.lambda_cr) << c.name;
    EXPECT_NEAR(s.frequency_hz, r.frequency_hz, 0.01 * r.frequency_hz) << c.name;
    if (c.radius == 0.0 && !c.clamped && c.b == c.a) {
      flat = s.lambda;
      flat_ref = r.lambda_cr;
      EXPECT_NEAR(s.lambda, 512.0, 0.01 * 512.0);  // Dowell's simply supported square
    }
    if (c.radius > 0.0) {
      // The curvature's effect on the boundary: the two models' ratios to the flat square.
      std::printf("curved / flat: %.5f (Ritz %.5f)\n", s.lambda / flat, r.lambda_cr / flat_ref);
      EXPECT_NEAR(s.lambda / flat, r.lambda_cr / flat_ref, 1e-3);
    }
  }
}

}  // namespace
}  // namespace shellflow::coupling
