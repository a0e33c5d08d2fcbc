#pragma once
// The nodal fields of the flow that probes and output read, one array per quantity, and
// their probe views (the names of case-format.md's `fluid.*` probe quantities).
#include <vector>

#include "shellflow/io/probes.h"

namespace shellflow::app {

struct FluidFields {
  std::vector<double> density, pressure, temperature, mach, energy;  ///< one per node
  std::vector<double> velocity, momentum, mesh_velocity;             ///< three per node

  /// Views of every field for the probes (the arrays must outlive them).
  std::vector<io::FieldView> views() const {
    return {{"fluid", "density", 1, density},   {"fluid", "pressure", 1, pressure},
            {"fluid", "temperature", 1, temperature}, {"fluid", "mach", 1, mach},
            {"fluid", "energy", 1, energy},     {"fluid", "velocity", 3, velocity},
            {"fluid", "momentum", 3, momentum}, {"fluid", "mesh_velocity", 3, mesh_velocity}};
  }
};

}  // namespace shellflow::app
