// Poisson/thickness locking diagnostic (shell.md §3, §13 item 6): a cantilever plate strip in
// cylindrical bending (symmetry planes on both long edges), nu = 0.3, small end shear. With
// the free thickness parameter `a` the tip deflection is the plate-strip value
// P L^3 / (3 D) + P L / (k G h), D = E h^3 / (12 (1 - nu^2)); with a = 0 everywhere the strip
// is stiffer by (1 - nu)^2 / (1 - 2 nu) = 1.225.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "shellflow/mesh/gmsh_io.h"
#include "shellflow/shell/static_solver.h"

namespace shellflow::shell {
namespace {

double tip_deflection(bool lock_a) {
  mesh::MeshingOptions meshing;
  meshing.order = 3;
  ShellSection section;
  section.thickness = 0.1;
  section.material = {1.2e6, 0.3, 0.0};
  ShellModel model(
      mesh::generate_mesh(std::filesystem::path(SHELLFLOW_SOURCE_DIR) / "cases/shell/sze31_cantilever_8x1.geo", meshing,
                          "shell"),
      section);
  model.add_support(Support::clamped("clamped"));
  model.add_support(Support::symmetry_plane("sides", 1));
  if (lock_a) model.add_support({"strip", {}, {}, true});
  model.add_line_load({"tip", Vec3(0.0, 0.0, 1e-3)});
  StaticSolver solver(model);
  solver.run(1, 1.0);
  return model.mean_displacement("tip", solver.displacement()).z();
}

TEST(PoissonLocking, FreeThicknessParameterGivesPlateStripBending) {
  const double E = 1.2e6, nu = 0.3, h = 0.1, L = 10.0, P = 1e-3;
  const double D = E * h * h * h / (12.0 * (1.0 - nu * nu));
  const double shear = P * L / (5.0 / 6.0 * E / (2.0 * (1.0 + nu)) * h);
  const double w_theory = P * L * L * L / (3.0 * D) + shear;
  const double w_free = tip_deflection(false);
  const double w_locked = tip_deflection(true);
  std::printf("tip deflection: free a %.6e, theory %.6e (ratio %.5f); a = 0: %.6e, stiffening %.4f (expected %.4f)\n",
              w_free, w_theory, w_free / w_theory, w_locked, w_free / w_locked,
              (1.0 - nu) * (1.0 - nu) / (1.0 - 2.0 * nu));
  EXPECT_NEAR(w_free / w_theory, 1.0, 2e-4);
  EXPECT_NEAR(w_free / w_locked, (1.0 - nu) * (1.0 - nu) / (1.0 - 2.0 * nu), 2e-3);
}

}  // namespace
}  // namespace shellflow::shell
