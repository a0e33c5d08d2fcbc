#pragma once
// How many fluid cells carry the wall pressure of the shell's modes (docs/fluid.md, "Cells
// per wavelength"): the wave a mode sends into a supersonic stream has the mode's streamwise
// wavelength λ_x along the wall and λ_x/M normal to its Mach front, and the flow's error
// per wavelength is set by the cells across that.
#include <string>
#include <vector>

#include "shellflow/mesh/mesh.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::coupling {

struct ModeResolution {
  int mode = 0;                   ///< 1-based index among the in-vacuo modes
  double frequency_hz = 0.0;      ///< in vacuo
  double wavelength = 0.0;        ///< λ_x = 2π/k_x along the stream [m]
  double front_wavelength = 0.0;  ///< λ_x/M for M > 1, else λ_x [m]
  double cells = 0.0;             ///< front_wavelength / cell_size
};

struct WallResolution {
  double cell_size = 0.0;  ///< mean extent of the wet faces along the stream [m]
  double mach = 0.0;
  std::vector<ModeResolution> modes;
};

/// The first `count` in-vacuo modes of the shell that move mostly out of its plane (normal
/// displacement carries more than half of the nodal displacement's square), their
/// streamwise wavenumber k_x (mesh::directional_wavenumber of the normal displacement
/// along `direction`), and the cells of the fluid's wet group `wet_group` per λ_x/M.
WallResolution wall_resolution(const shell::ShellModel& shell, const mesh::Mesh& fluid, const std::string& wet_group,
                               const Vec3& direction, double mach, int count = 2);

/// `{"cell_size": ..., "mach": ..., "modes": [{"mode": ..., ...}, ...]}`
std::string to_json(const WallResolution& r);

}  // namespace shellflow::coupling
