#pragma once
// The output of one mesh's fields, shared by every kind of run: the probe views of the
// mesh's current state and its frames (<mesh>_NNNNNN.vtu + <mesh>.pvd).
//
// A run kind creates the outputs of the meshes it moves and hands them to the Recorder
// (recorder.h); the meshes it does not move keep their initial state (InitialOutput).
// Probe views are lazy where the fields are derived (the flow's primitive variables, a
// mesh's displacement): the probes read their few nodes, and the whole field is built only
// when a frame is written.
#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "shellflow/fluid/fluid_model.h"
#include "shellflow/io/case.h"
#include "shellflow/io/probes.h"
#include "shellflow/io/pvd_writer.h"
#include "shellflow/io/vtu_writer.h"
#include "shellflow/motion/space_mesh.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::run {

class MeshOutput {
 public:
  MeshOutput(const mesh::Mesh& mesh, const std::filesystem::path& outdir, io::OutputMode mode);
  virtual ~MeshOutput() = default;
  MeshOutput(const MeshOutput&) = delete;
  MeshOutput& operator=(const MeshOutput&) = delete;

  /// The case mesh this output writes ("fluid", "space", "shell").
  const std::string& key() const { return mesh_.name; }
  /// Probe views of the current state; they read the state when sampled.
  virtual std::vector<io::FieldView> views() const = 0;
  /// Writes <mesh>_<step>.vtu of the current state at time (or load level) t and adds it to
  /// <mesh>.pvd.
  virtual void write(long step, double t) = 0;
  /// Called on every rank before the probes read views() (a distributed flow gathers the
  /// probed nodes' values from their owners here).
  virtual void prepare_sample() {}
  io::PvdWriter& pvd() { return pvd_; }

  /// A distributed run's frames: each rank writes its piece `<mesh>_<step>_p<rank>.vtu` of
  /// `piece` (the cells it owns), rank 0 the `<mesh>_<step>.pvtu` that joins the `count`
  /// pieces, and the `.pvd` lists the `.pvtu`. `piece` must outlive the output.
  void set_pieces(const mesh::Mesh& piece, int rank, int count);

 protected:
  /// The frame itself: the fields on the mesh (or this rank's piece) at `positions` (empty:
  /// the mesh's nodes).
  void write_frame(long step, double t, std::vector<io::VtuField> fields, std::span<const Vec3> positions = {});

  const mesh::Mesh& mesh_;

 private:
  struct Pieces {
    const mesh::Mesh* mesh = nullptr;
    int rank = 0;
    int count = 1;
  };
  std::filesystem::path outdir_;
  io::PvdWriter pvd_;
  std::optional<Pieces> pieces_;
};

/// The initial state of a mesh no solver of the run moves: the shell at rest, the fluid at
/// its free stream (when the case has a fluid section), the space mesh undeformed. Fixed
/// arrays; written as frame 0 only.
class InitialOutput final : public MeshOutput {
 public:
  InitialOutput(const io::Case& c, const mesh::Mesh& mesh, const std::filesystem::path& outdir);
  std::vector<io::FieldView> views() const override;
  void write(long step, double t) override;

 private:
  std::vector<std::pair<std::string, int>> names_;  ///< quantity, components
  std::vector<std::vector<double>> values_;
};

/// The shell's fields from its state (u, v; v null: at rest): displacement, velocity,
/// position (probes), plus director, thickness parameter and stresses (VTU).
class ShellOutput final : public MeshOutput {
 public:
  using State = std::function<const Eigen::VectorXd&()>;
  using Velocity = std::function<const Eigen::VectorXd*()>;
  ShellOutput(const shell::ShellModel& model, const std::filesystem::path& outdir,
              io::OutputSection::ShellStress stress, io::OutputMode mode, State u, Velocity v);
  std::vector<io::FieldView> views() const override;
  void write(long step, double t) override;

 private:
  const shell::ShellModel& model_;
  io::OutputSection::ShellStress stress_;
  State u_;
  Velocity v_;
};

/// The flow's fields in the case mesh's node order (the solver runs on a renumbered copy:
/// new_index[i] is the solver's node of case node i).
struct FluidPieces;
class ProbeGather;

class FluidOutput final : public MeshOutput {
 public:
  FluidOutput(const mesh::Mesh& case_mesh, std::span<const Index> new_index, fluid::FluidModel& model,
              const std::filesystem::path& outdir, io::OutputMode mode);
  /// A rank's output of a distributed flow (fluid_pieces.h): frames of its piece, probe views
  /// of every case node from their owners. `pieces` must outlive the output.
  FluidOutput(const mesh::Mesh& case_mesh, const FluidPieces& pieces, fluid::FluidModel& model,
              const std::filesystem::path& outdir, io::OutputMode mode);
  ~FluidOutput() override;
  std::vector<io::FieldView> views() const override;
  void prepare_sample() override;
  void write(long step, double t) override;

 private:
  /// Quantity `q` (kFluidQuantities' index) at the model's node k.
  void value(std::size_t q, Index k, double* out) const;
  std::span<const Index> new_index_;  ///< case node -> model node
  fluid::FluidModel& model_;          ///< non-const: the frames' artificial viscosity is computed on demand
  const FluidPieces* pieces_ = nullptr;
  std::unique_ptr<ProbeGather> gather_;
};

/// A fluid mesh moved without a flow (mesh-motion runs, coupled runs without loads):
/// displacement (from the mover's reference positions, e.g. with the wall nodes snapped onto
/// the shell) and mesh velocity from the mover's positions and velocities, all in the
/// solver's node order `new_index` maps (empty: the case's).
class FluidMeshOutput final : public MeshOutput {
 public:
  using Nodal = std::function<std::span<const Vec3>()>;
  FluidMeshOutput(const mesh::Mesh& case_mesh, std::span<const Index> new_index, std::span<const Vec3> reference,
                  Nodal positions, Nodal velocity, const std::filesystem::path& outdir, io::OutputMode mode);
  std::vector<io::FieldView> views() const override;
  void write(long step, double t) override;

 private:
  std::size_t node(Index i) const {
    return new_index_.empty() ? std::size_t(i) : std::size_t(new_index_[std::size_t(i)]);
  }
  std::span<const Index> new_index_;
  std::span<const Vec3> reference_;
  Nodal positions_, velocity_;
};

/// The space mesh of a SpaceMeshMover: displacement and velocity of its nodes.
class SpaceMeshOutput final : public MeshOutput {
 public:
  SpaceMeshOutput(const mesh::Mesh& case_mesh, const motion::SpaceMesh& space, const std::filesystem::path& outdir,
                  io::OutputMode mode);
  std::vector<io::FieldView> views() const override;
  void write(long step, double t) override;

 private:
  const motion::SpaceMesh& space_;
};

/// Node-major 3-vectors of the dofs [offset, offset + 3) of every node of a shell vector.
std::vector<double> nodal_part(const Eigen::VectorXd& u, Index nodes, int offset);
/// Flattens 3-vectors.
std::vector<double> flatten(std::span<const Vec3> v);

}  // namespace shellflow::run
