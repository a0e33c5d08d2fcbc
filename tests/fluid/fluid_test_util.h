#pragma once
// Shared helpers of the fluid tests: case meshes, time marching to a given time.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "shellflow/core/version.h"
#include "shellflow/fluid/fluid_model.h"
#include "shellflow/fluid/ordering.h"
#include "shellflow/mesh/gmsh_io.h"

namespace shellflow::fluid::test_support {

inline std::filesystem::path fluid_case(const std::string& file) {
  return std::filesystem::path(shellflow::source_dir) / "cases" / "fluid" / file;
}

/// Meshes a case .geo of cases/fluid and renumbers it for locality.
inline mesh::Mesh case_mesh(const std::string& geo) {
  mesh::MeshingOptions options;
  options.order = 1;
  mesh::Mesh m = mesh::generate_mesh(fluid_case(geo), options, "fluid");
  renumber_for_locality(m);
  return m;
}

/// Marches a fixed-mesh model to t_end with the global stable step times cfl.
inline int run_until(FluidModel& model, double t_end, double cfl) {
  int steps = 0;
  while (model.time() < t_end * (1 - 1e-14)) {
    const double dt = std::min(model.stable_dt(cfl), t_end - model.time());
    model.step(dt);
    ++steps;
  }
  return steps;
}

/// Marches to t_end while the nodes follow x = motion(X, t) (X: initial positions); the
/// mesh velocity of each step is the node displacement over the step.
template <class Motion>
int run_until_moving(FluidModel& model, double t_end, double cfl, Motion&& motion) {
  const std::vector<Vec3> X(model.positions().begin(), model.positions().end());
  std::vector<Vec3> x(X.size());
  int steps = 0;
  while (model.time() < t_end * (1 - 1e-14)) {
    const double dt = std::min(model.stable_dt(cfl), t_end - model.time());
    for (std::size_t a = 0; a < X.size(); ++a) x[a] = motion(X[a], model.time() + dt);
    model.step(dt, x);
    ++steps;
  }
  return steps;
}

}  // namespace shellflow::fluid::test_support
