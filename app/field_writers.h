#pragma once
// One output writer per mesh, shared by every kind of run: the probe views of a mesh's
// current fields and its <mesh>_NNNNNN.vtu + <mesh>.pvd frames.
#include <filesystem>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "fluid_fields.h"
#include "shellflow/fluid/fluid_model.h"
#include "shellflow/io/case.h"
#include "shellflow/io/probes.h"
#include "shellflow/io/pvd_writer.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::app {

/// The shell's fields: displacement, velocity, position (probes), plus director, thickness
/// parameter and stresses (VTU).
class ShellWriter {
 public:
  ShellWriter(const shell::ShellModel& model, const std::filesystem::path& outdir,
              io::OutputSection::ShellStress stress, io::OutputMode mode = io::OutputMode::create);
  /// Updates the fields from the state (u, v; v null: at rest) and returns their probe views.
  std::vector<io::FieldView> update(const Eigen::VectorXd& u, const Eigen::VectorXd* v);
  /// Writes shell_<step>.vtu of the last update() at time t and adds it to shell.pvd.
  void write(long step, double t, const Eigen::VectorXd& u);
  io::PvdWriter& pvd() { return pvd_; }

 private:
  const shell::ShellModel& model_;
  std::filesystem::path outdir_;
  io::OutputSection::ShellStress stress_;
  io::PvdWriter pvd_;
  std::vector<double> displacement_, velocity_, position_, director_, thickness_;
};

/// The flow's fields in the case mesh's node order (the solver runs on a renumbered copy:
/// new_index[i] is the solver's node of case node i).
class FluidWriter {
 public:
  FluidWriter(const mesh::Mesh& case_mesh, std::vector<Index> new_index, const std::filesystem::path& outdir,
              io::OutputMode mode = io::OutputMode::create);
  std::vector<io::FieldView> update(const fluid::FluidModel& model);
  void write(long step, fluid::FluidModel& model);
  io::PvdWriter& pvd() { return pvd_; }

 private:
  const mesh::Mesh& mesh_;
  std::vector<Index> new_index_;
  std::filesystem::path outdir_;
  io::PvdWriter pvd_;
  FluidFields fields_;
  std::vector<Vec3> positions_;
};

/// Node-major 3-vectors of the dofs [offset, offset + 3) of every node of a shell vector.
std::vector<double> nodal_part(const Eigen::VectorXd& u, Index nodes, int offset);
/// Flattens 3-vectors.
std::vector<double> flatten(std::span<const Vec3> v);

}  // namespace shellflow::app
