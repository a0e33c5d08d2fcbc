// The shell's natural frequencies and modes as output files.
#include "shellflow/run/shell_modes.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <span>
#include <string>
#include <string_view>

#include "shellflow/core/error.h"
#include "shellflow/core/output_file.h"
#include "shellflow/io/mesh_output.h"
#include "shellflow/io/pvd_writer.h"
#include "shellflow/run/mesh_outputs.h"
#include "shellflow/shell/modal.h"

namespace shellflow::run {
namespace {

/// One mode of the modal analysis for the output: the mid-surface displacement scaled to a
/// largest nodal |Δx| of 1 (M-normalised amplitudes have units of kg^-1/2 and differ by
/// orders between modes, which makes Warp By Vector useless), its sign fixed so that the
/// largest component is positive, and the shares of its kinetic energy φ·(Mφ) on the x, y, z
/// translation rows (the rest is the directors' rotary inertia).
struct ModeShape {
  std::vector<double> displacement;
  Vec3 kinetic = Vec3::Zero();
  char direction = 'x';
};

ModeShape mode_shape(const Eigen::VectorXd& phi, const Eigen::VectorXd& M_phi, Index nodes) {
  ModeShape m;
  m.displacement = normalised_mode_displacement(phi, nodes);
  for (Index n = 0; n < nodes; ++n)
    for (int i = 0; i < 3; ++i) m.kinetic(i) += phi(shell::dofs_per_node * n + i) * M_phi(shell::dofs_per_node * n + i);
  Eigen::Index axis = 0;
  m.kinetic.maxCoeff(&axis);
  m.direction = "xyz"[axis];
  return m;
}

}  // namespace

std::vector<double> normalised_mode_displacement(const Eigen::VectorXd& phi, Index nodes) {
  std::vector<double> d = nodal_part(phi, nodes, 0);
  double largest = 0.0;
  for (const double x : d)
    if (std::abs(x) > std::abs(largest)) largest = x;
  double norm = 0.0;
  for (std::size_t k = 0; k < d.size(); k += 3) norm = std::max(norm, std::hypot(d[k], d[k + 1], d[k + 2]));
  const double scale = norm > 0.0 ? std::copysign(1.0 / norm, largest) : 1.0;
  for (double& x : d) x *= scale;
  return d;
}

namespace {

/// The frequencies and modes, `FILE:LINE: shell.analysis: what` when the iteration fails.
shell::ModalResult solve(const io::ShellAnalysis& analysis, const shell::ShellModel& model) {
  shell::ModalOptions options;
  options.tolerance = analysis.modal_tolerance;
  options.max_iterations = analysis.modal_max_iterations;
  try {
    return shell::natural_frequencies(model, analysis.modes, Eigen::VectorXd::Zero(model.num_dofs()), options);
  } catch (const SolverError& e) {
    std::string_view what = e.what();  // the module's own prefix dropped
    if (what.starts_with("shell modal analysis: ")) what.remove_prefix(22);
    // Supports that leave a mechanism: the case's to fix, not a run the physics stopped.
    throw InputError(analysis.where.message(what));
  }
}

/// modes.csv and modes.json; returns the table for the log.
std::string write_tables(const shell::ModalResult& result, std::span<const ModeShape> shapes, double tolerance,
                         const std::filesystem::path& outdir) {
  std::string csv = "mode,frequency_hz,angular_frequency,direction,kinetic_x,kinetic_y,kinetic_z\n";
  std::string table = fmt::format("{:>5} {:>14} {:>16} {:>9}  kinetic energy x / y / z", "mode", "frequency [Hz]",
                                  "omega [rad/s]", "direction");
  std::string json_frequencies;
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const double f = result.frequencies[k];
    const double omega = 2.0 * std::numbers::pi * f;
    const ModeShape& m = shapes[k];
    csv += fmt::format("{},{:.10g},{:.10g},{},{:.6f},{:.6f},{:.6f}\n", k + 1, f, omega, m.direction, m.kinetic.x(),
                       m.kinetic.y(), m.kinetic.z());
    table += fmt::format("\n{:>5} {:>14.6f} {:>16.6f} {:>9}  {:.3f} / {:.3f} / {:.3f}", k + 1, f, omega, m.direction,
                         m.kinetic.x(), m.kinetic.y(), m.kinetic.z());
    json_frequencies += fmt::format("{}{:.17g}", k ? ", " : "", f);
  }
  write_file_atomically(outdir / "modes.csv", csv);
  write_file_atomically(
      outdir / "modes.json",
      fmt::format("{{\"modes\": {}, \"frequencies_hz\": [{}], \"iterations\": {}, \"tolerance\": {:.17g}}}\n",
                  shapes.size(), json_frequencies, result.iterations, tolerance));
  return table;
}

/// Both layouts of the shapes: shell_modes.vtu holds all of them side by side (compare
/// modes, pick one in Warp By Vector), modes.pvd steps through them with ParaView's time
/// controls (time = mode number; one `displacement` array, as in the dynamic runs).
void write_shapes(const mesh::Mesh& mesh, std::span<const ModeShape> shapes, const std::filesystem::path& outdir) {
  std::vector<io::VtuField> all;
  for (std::size_t k = 0; k < shapes.size(); ++k)
    all.push_back({fmt::format("mode_{:02}", k + 1), 3, shapes[k].displacement});
  io::write_mesh_vtu(outdir / "shell_modes.vtu", mesh, std::move(all));
  io::PvdWriter pvd(outdir, "modes");
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const std::string vtu = fmt::format("shell_mode_{:02}.vtu", k + 1);
    io::write_mesh_vtu(outdir / vtu, mesh, {{"displacement", 3, shapes[k].displacement}}, static_cast<double>(k + 1));
    pvd.add(static_cast<double>(k + 1), vtu);
  }
}

}  // namespace

void write_modes(const io::Case& c, const shell::ShellModel& model, const std::filesystem::path& outdir) {
  const io::ShellAnalysis& analysis = *c.shell->analysis;
  if (!c.shell->loads.empty())
    spdlog::warn("modal analysis about the undeformed shell: its {} load(s) are not applied (no pre-stress)",
                 c.shell->loads.size());
  const auto start = std::chrono::steady_clock::now();
  const shell::ModalResult result = solve(analysis, model);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  shell::SparseMatrix M = model.make_matrix();
  model.assemble_mass(M);
  std::vector<ModeShape> shapes;
  for (const Eigen::VectorXd& phi : result.modes) shapes.push_back(mode_shape(phi, M * phi, model.num_nodes()));
  const std::string table = write_tables(result, shapes, analysis.modal_tolerance, outdir);
  write_shapes(model.mesh(), shapes, outdir);
  spdlog::info("shell modal analysis: {} modes in {} subspace iterations ({:.2f} s)\n{}", shapes.size(),
               result.iterations, seconds, table);
  spdlog::info("wrote modes.csv, modes.json, shell_modes.vtu (arrays mode_01...), modes.pvd (shell_mode_NN.vtu)");
}

}  // namespace shellflow::run
