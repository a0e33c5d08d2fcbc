#pragma once
// The plane-strain strip of the linear flutter tests: the paper's aluminium panel (0.5 m,
// 1.35 mm) as nx cubic elements along the flow, piston theory at Mach 2.3 under the paper's air.
#include <cmath>

#include "../shell/structured_shell_mesh.h"
#include "coupling_test_util.h"
#include "shellflow/coupling/piston_theory.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::coupling::test_strip {

inline constexpr double a = 0.5, width = 0.025, h = 1.35e-3, E = 77.28e9, nu = 0.33, rho_m = 2710.0;

enum class Edges { clamped, pinned };

/// nx cubic elements along x (the flow), one across, symmetry planes y = 0 and y = width, the
/// edges x = 0 and x = a clamped or pinned (soft simple support).
inline shell::ShellModel strip(int nx, Edges edges) {
  mesh::Mesh m =
      shell::testing::structured_shell_mesh(a, width, nx, 1, [](double s, double t) { return Vec3(s, t, 0.0); });
  shell::ShellSection section;
  section.thickness = h;
  section.material = {E, nu, rho_m};
  shell::ShellModel model(std::move(m), section);
  for (const char* g : {"left", "right"})
    model.add_support(edges == Edges::clamped ? shell::Support::clamped(g) : shell::Support::simply_supported(g));
  for (const char* g : {"bottom", "top"}) model.add_support(shell::Support::symmetry_plane(g, 1));
  return model;
}

/// Piston theory at Mach 2.3, 0.339 kg/m^3, 28 kPa, the flow along x over the face +z.
inline PistonTheoryFlow piston_flow(double mach = 2.3) {
  PistonTheoryFlow flow;
  flow.density = 0.339;
  flow.mach = mach;
  flow.speed = mach * std::sqrt(1.4 * 28000.0 / 0.339);
  flow.direction = Vec3::UnitX();
  flow.wet_normal = Vec3::UnitZ();
  return flow;
}

inline PistonTheory piston(const shell::ShellModel& model) { return PistonTheory(model, piston_flow()); }

inline FlutterSetting setting(bool damping) { return coupling_test::panel_flutter_setting(a, 2.3, damping); }

}  // namespace shellflow::coupling::test_strip
