#include "shellflow/coupling/wall_resolution.h"

#include <fmt/format.h>

#include <numbers>

#include "shellflow/core/json.h"
#include "shellflow/mesh/surface_fields.h"
#include "shellflow/shell/modal.h"

namespace shellflow::coupling {

WallResolution wall_resolution(const shell::ShellModel& shell, const mesh::Mesh& fluid, const std::string& wet_group,
                               const Vec3& direction, double mach, int count) {
  WallResolution r;
  r.mach = mach;
  r.cell_size = mesh::mean_extent(fluid, fluid.group(wet_group).elements, direction);
  // Twice the modes asked for: in-plane modes are skipped.
  const shell::ModalResult modal =
      shell::natural_frequencies(shell, 2 * count + 2, Eigen::VectorXd::Zero(shell.num_dofs()));
  const Index nodes = shell.num_nodes();
  std::vector<double> w(static_cast<std::size_t>(nodes));
  for (std::size_t m = 0; m < modal.modes.size() && static_cast<int>(r.modes.size()) < count; ++m) {
    const Eigen::VectorXd& phi = modal.modes[m];
    double normal = 0.0, total = 0.0;
    for (Index n = 0; n < nodes; ++n) {
      const Vec3 d = phi.segment<3>(shell::dofs_per_node * n);
      w[static_cast<std::size_t>(n)] = d.dot(shell.directors()[static_cast<std::size_t>(n)]);
      normal += w[static_cast<std::size_t>(n)] * w[static_cast<std::size_t>(n)];
      total += d.squaredNorm();
    }
    if (!(normal > 0.5 * total)) continue;
    ModeResolution row;
    row.mode = static_cast<int>(m) + 1;
    row.frequency_hz = modal.frequencies[m];
    row.wavelength = 2.0 * std::numbers::pi / mesh::directional_wavenumber(shell.mesh(), w, direction);
    row.front_wavelength = mach > 1.0 ? row.wavelength / mach : row.wavelength;
    row.cells = row.front_wavelength / r.cell_size;
    r.modes.push_back(row);
  }
  return r;
}

std::string to_json(const WallResolution& r) {
  std::string modes;
  for (const ModeResolution& m : r.modes)
    modes += fmt::format(
        "{}{{\"mode\": {}, \"frequency_hz\": {}, \"wavelength\": {}, \"front_wavelength\": {}, \"cells\": {}}}",
        modes.empty() ? "" : ", ", m.mode, json_number(m.frequency_hz), json_number(m.wavelength),
        json_number(m.front_wavelength), json_number(m.cells));
  return fmt::format("{{\"cell_size\": {}, \"mach\": {}, \"modes\": [{}]}}", json_number(r.cell_size),
                     json_number(r.mach), modes);
}

}  // namespace shellflow::coupling
