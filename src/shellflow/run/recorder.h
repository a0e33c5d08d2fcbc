#pragma once
// What a run records of its state: the probe row (probes.csv) and the frames of every mesh
// (<mesh>_NNNNNN.vtu + <mesh>.pvd), the run kind's own CSVs registered beside them.
//
// Every case mesh starts with its initial output (the shell at rest, the fluid at the free
// stream, the space mesh undeformed); a run kind replaces the outputs of the meshes it moves
// with its own (add). Frame 0 is written once, by record(0, ...) of a new run: the run kind's
// outputs from the solvers' initial state, the initial outputs for the other meshes.
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "shellflow/io/case.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/io/probes.h"
#include "shellflow/run/mesh_outputs.h"
#include "shellflow/run/run_control.h"

namespace shellflow::run {

/// What record() writes of the current state.
enum class Record {
  probes,             ///< the probe rows (every step)
  probes_and_fields,  ///< the probe rows and the fields' frames (every output.every steps, the last)
  fields,             ///< the fields' frames only (a stopped run's or a failed run's last state)
};

class Recorder {
 public:
  /// Locates the probes (probes.csv opened in `mode`) and sets up the initial output of
  /// every mesh of `meshes`.
  Recorder(const io::Case& c, const io::CaseMeshes& meshes, const std::filesystem::path& outdir, io::OutputMode mode);

  /// The output of a mesh the run moves: its frames and probe views replace the initial ones.
  void add(MeshOutput& output);
  /// A CSV the run kind appends to itself (it joins the checkpoints).
  void add(io::ProbeWriter& csv) { csvs_.push_back(&csv); }
  /// Called with the time and the values of every probe row recorded.
  void on_sample(std::function<void(double t, std::span<const double> probes)> f) { on_sample_ = std::move(f); }
  /// Registers the writers with `control` for checkpoints: probes.csv, the run kind's mesh
  /// outputs and CSVs, in the order added.
  void register_outputs(RunControl& control);

  /// Records the current state at time (or load level) t as step `step`.
  void record(long step, double t, Record what);
  /// The probe views of the current state (the run kind's, then the initial ones).
  std::vector<io::FieldView> views() const;
  io::ProbeSet& probes() { return probes_; }
  /// Wall seconds spent in record() so far.
  double seconds() const { return seconds_; }

 private:
  io::ProbeSet probes_;
  std::vector<std::unique_ptr<InitialOutput>> initial_;
  std::vector<MeshOutput*> outputs_;  ///< the run kind's
  std::vector<io::ProbeWriter*> csvs_;
  std::function<void(double, std::span<const double>)> on_sample_;
  double seconds_ = 0.0;
};

}  // namespace shellflow::run
