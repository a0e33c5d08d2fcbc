#include "shellflow/run/coupling_log.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>

namespace shellflow::run {

CouplingLog::CouplingLog(const std::filesystem::path& csv, io::OutputMode mode)
    : csv_(csv,
           {"newton_iterations", "coupling_iterations", "coupling_residual", "substeps", "shell_force_x",
            "shell_force_y", "shell_force_z", "fluid_force_x", "fluid_force_y", "fluid_force_z", "force_balance"},
           mode) {}

double CouplingLog::step(coupling::PartitionedSolver& driver, double dt, long step) {
  const auto t0 = std::chrono::steady_clock::now();
  const coupling::CouplingStepReport r = driver.step(dt);
  steps_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  steps_ = step;
  shell_seconds_ += r.shell_seconds;
  mesh_seconds_ += r.flow.mesh_seconds;
  flow_seconds_ += r.flow.flow_seconds;
  transfer_seconds_ += r.transfer_seconds;
  iteration_seconds_ += r.iteration_seconds;
  newton_total_ += r.newton_iterations;
  coupling_total_ += r.coupling_iterations;
  substeps_total_ += long(r.flow.substeps) * r.coupling_iterations;  // every iteration's flow pass
  const Vec3 ff = r.fluid_force.value_or(Vec3::Constant(std::nan("")));
  const double scale = std::max(r.shell_force.norm(), ff.allFinite() ? ff.norm() : 0.0);
  const double balance = ff.allFinite() && scale > 0.0 ? (r.shell_force - ff).norm() / scale : 0.0;
  worst_balance_ = std::max(worst_balance_, balance);
  csv_.append(r.time, std::vector<double>{double(r.newton_iterations), double(r.coupling_iterations),
                                          r.coupling_residual, double(r.flow.substeps), r.shell_force.x(),
                                          r.shell_force.y(), r.shell_force.z(), ff.x(), ff.y(), ff.z(), balance});
  spdlog::debug(
      "step {} t = {:.6g} s: {} Newton iterations, {} coupling iterations (load residual {:.2e}), {} fluid "
      "sub-steps, shell force ({:.4g}, {:.4g}, {:.4g}) N, force balance {:.2e}",
      step, r.time, r.newton_iterations, r.coupling_iterations, r.coupling_residual, r.flow.substeps, r.shell_force.x(),
      r.shell_force.y(), r.shell_force.z(), balance);
  return r.time;
}

void CouplingLog::summary(double time, double output_seconds) const {
  spdlog::info(
      "coupled run: {} shell steps to t = {:.6g} s, {} Newton iterations, {} coupling iterations ({:.2f} per "
      "step), {} fluid sub-steps; largest force imbalance {:.2e}",
      steps_, time, newton_total_, coupling_total_, steps_ > 0 ? double(coupling_total_) / double(steps_) : 0.0,
      substeps_total_, worst_balance_);
  spdlog::info(
      "wall time {:.2f} s: setup {:.2f} s, shell {:.2f} s, fluid mesh motion {:.2f} s, flow {:.2f} s, load "
      "transfer {:.2f} s, coupling iterations {:.2f} s, output {:.2f} s",
      setup_seconds_ + steps_seconds_ + output_seconds, setup_seconds_, shell_seconds_, mesh_seconds_, flow_seconds_,
      transfer_seconds_, iteration_seconds_, output_seconds);
}

void CouplingLog::save(ArchiveWriter& out) const {
  out.put(newton_total_);
  out.put(coupling_total_);
  out.put(substeps_total_);
  out.put(worst_balance_);
}

void CouplingLog::restore(ArchiveReader& in) {
  newton_total_ = in.get<long>();
  coupling_total_ = in.get<long>();
  substeps_total_ = in.get<long>();
  worst_balance_ = in.get<double>();
}

}  // namespace shellflow::run
