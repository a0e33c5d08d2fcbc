#pragma once
// The record of a coupled run's shell steps: coupling.csv (Newton and coupling iterations,
// the coupling residual, fluid
// sub-steps, the shell's and the fluid's resultant forces and their balance per step), the
// totals for the summary, and the wall time by part.
#include <filesystem>

#include "shellflow/core/archive.h"
#include "shellflow/coupling/partitioned_solver.h"
#include "shellflow/io/probe_writer.h"

namespace shellflow::run {

class CouplingLog {
 public:
  CouplingLog(const std::filesystem::path& csv, io::OutputMode mode);
  /// Makes shell step `step` of `driver` and records it; returns the time reached.
  double step(coupling::PartitionedSolver& driver, double dt, long step);
  void add_setup_seconds(double s) { setup_seconds_ += s; }
  /// Logs the totals and the wall time by part (`output_seconds`: the recorder's).
  void summary(double time, double output_seconds) const;
  io::ProbeWriter& csv() { return csv_; }
  /// Checkpoint: the totals (the wall times start again).
  void save(ArchiveWriter& out) const;
  void restore(ArchiveReader& in);

 private:
  io::ProbeWriter csv_;
  long steps_ = 0, newton_total_ = 0, coupling_total_ = 0, substeps_total_ = 0;
  double worst_balance_ = 0.0;
  double setup_seconds_ = 0.0, steps_seconds_ = 0.0, shell_seconds_ = 0.0, mesh_seconds_ = 0.0, flow_seconds_ = 0.0,
         transfer_seconds_ = 0.0, iteration_seconds_ = 0.0;
};

}  // namespace shellflow::run
