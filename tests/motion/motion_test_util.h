#pragma once
// Shared set-up of the motion tests: the panel-flutter meshes, generated once per process.
#include <filesystem>

#include "shellflow/core/version.h"
#include "shellflow/mesh/gmsh_io.h"
#include "shellflow/motion/mesh_mover.h"

namespace motion_test {

inline const std::filesystem::path panel_dir = std::filesystem::path(shellflow::source_dir) / "cases" / "panel_flutter";

inline shellflow::mesh::Mesh generate(const char* geo, int order, const char* name) {
  shellflow::mesh::MeshingOptions options;
  options.order = order;
  return shellflow::mesh::generate_mesh(panel_dir / geo, options, name);
}

inline const shellflow::mesh::Mesh& fluid() {
  static const auto m = generate("fluid_slab.geo", 1, "fluid");
  return m;
}
inline const shellflow::mesh::Mesh& space() {
  static const auto m = generate("space_mesh.geo", 3, "space");
  return m;
}
inline const shellflow::mesh::Mesh& shell() {
  static const auto m = generate("panel_strip.geo", 3, "shell");
  return m;
}

inline shellflow::motion::BoundaryGroups panel_groups() {
  return {{"panel"}, {"inflow", "outflow", "far_field", "wall"}, {"symmetry"}};
}

inline shellflow::motion::SpaceMeshOptions panel_options(
    double exponent = 4.0, shellflow::motion::IdwWeighting weighting = shellflow::motion::IdwWeighting::plain) {
  shellflow::motion::SpaceMeshOptions o;
  const auto g = panel_groups();
  o.interface_groups = g.interface_groups;
  o.fixed_groups = g.fixed_groups;
  o.sliding_groups = g.sliding_groups;
  o.interface_exponent = o.fixed_exponent = exponent;
  o.weighting = weighting;
  return o;
}

/// Single-mode panel deflection A(t) sin(pi s / L) along +y on the panel 0.25 <= x <= 0.75.
inline shellflow::motion::PanelModesMotion panel_motion(shellflow::TimeFunction amplitude) {
  using shellflow::Vec3;
  return shellflow::motion::PanelModesMotion(Vec3(0.25, 0, 0), Vec3::UnitX(), 0.5, Vec3::UnitY(),
                                             {{1, std::move(amplitude)}});
}

/// Fluid node positions x and mesh velocities w at time t from a mover.
inline std::pair<std::vector<shellflow::Vec3>, std::vector<shellflow::Vec3>> at(
    shellflow::motion::FluidMeshMover& mover, double t) {
  std::vector<shellflow::Vec3> x(fluid().nodes.size()), w(x.size());
  mover.update(t, x, w);
  return {x, w};
}

}  // namespace motion_test
