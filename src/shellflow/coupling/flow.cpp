#include "shellflow/coupling/flow.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "shellflow/core/error.h"
#include "shellflow/mesh/quality.h"

namespace shellflow::coupling {

FlowModel::FlowModel(const mesh::Mesh& fluid_mesh, std::unique_ptr<fluid::FluidModel> flow,
                     std::unique_ptr<motion::FluidMeshMover> mover, ShellStepMotion& motion, WallNodeMap wall,
                     LoadPointMap loads, FlowModelOptions options)
    : mesh_(fluid_mesh),
      flow_(std::move(flow)),
      mover_(std::move(mover)),
      wall_(std::move(wall)),
      loads_(std::move(loads)),
      faces_(oriented_wet_faces(fluid_mesh, wall_.group)),
      options_(options),
      x_(fluid_mesh.nodes),
      w_(fluid_mesh.nodes.size(), Vec3::Zero()) {
  wall_handle_ = motion.register_shell_points(wall_.points);
  wall_displacement_.resize(wall_.nodes.size());
  wall_velocity_.resize(wall_.nodes.size());
  node_pressure_.resize(loads_.fluid_nodes.size());
  if (flow_) time_ = flow_->time();
  if (flow_ && flow_->options().gas.viscous())
    for (const fluid::BoundaryCondition& bc : flow_->boundaries().conditions())
      has_shear_ = has_shear_ || (bc.group == wall_.group && bc.kind == fluid::BoundaryKind::no_slip_wall);
  if (has_shear_) {
    wall_shear_.resize(wall_.nodes.size());
    for (const Index node : loads_.fluid_nodes) {
      const auto it = std::lower_bound(wall_.nodes.begin(), wall_.nodes.end(), node);
      if (it == wall_.nodes.end() || *it != node)
        throw Error(fmt::format("coupling: load-map node {} is not a node of the wet group '{}'", node, wall_.group));
      shear_slot_.push_back(std::size_t(it - wall_.nodes.begin()));
    }
  }
}

FlowStepReport FlowModel::substeps_for(double dt) {
  FlowStepReport r;
  if (!flow_) {
    if (options_.substeps <= 0)
      throw InputError(
          "coupling.substeps: a run without a flow has no stable step to size the "
          "sub-steps by; give coupling.substeps as a number");
    r.substeps = options_.substeps;
    return r;
  }
  const double stable = flow_->stable_dt(options_.cfl);
  r.stable_substeps = dt / stable;
  const int needed = static_cast<int>(std::ceil(r.stable_substeps * (1.0 - 1e-12)));
  if (options_.substeps <= 0) {
    r.substeps = std::max(1, needed);
  } else {
    if (options_.substeps < needed)
      throw SolverError(
          fmt::format("t = {:.6g} s: coupling.substeps = {} fluid steps per shell step is unstable here: the "
                      "stable fluid step at CFL {} is {:.4g} s, so the shell step of {:.4g} s needs at least "
                      "{} sub-steps; set coupling.substeps to {} or more (or auto)",
                      time_, options_.substeps, options_.cfl, stable, dt, needed, needed));
    r.substeps = options_.substeps;
  }
  return r;
}

namespace {
using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }
}  // namespace

FlowStepReport FlowModel::advance(const ShellStepMotion& motion, double t_end) {
  const double t0 = time_;
  const double dt = t_end - t0;
  auto c0 = Clock::now();
  FlowStepReport report = substeps_for(dt);
  report.flow_seconds += seconds(c0, Clock::now());
  const int n = report.substeps;
  // A failure inside the shell step puts the flow and the mesh back to t0, so that every
  // field of the last valid state is of the same time.
  std::optional<fluid::FluidSnapshot> start;
  if (flow_) start = flow_->snapshot();
  try {
    for (int m = 1; m <= n; ++m) {
      const double t = m == n ? t_end : t0 + dt * (static_cast<double>(m) / n);
      const auto c1 = Clock::now();
      // With w = Δx/Δt the mover's velocities are not needed: positions only.
      const bool positions_only = flow_ && !options_.interpolated_mesh_velocity;
      mover_->update(t, x_, positions_only ? std::span<Vec3>{} : std::span<Vec3>(w_));
      if (flow_) {
        motion.evaluate(wall_handle_, t, wall_displacement_, wall_velocity_);
        flow_->set_wall_velocity(wall_.group, wall_velocity_);
        const auto c2 = Clock::now();
        report.mesh_seconds += seconds(c1, c2);
        flow_->step(t - flow_->time(), x_,
                    options_.interpolated_mesh_velocity ? std::span<const Vec3>(w_) : std::span<const Vec3>{});
        report.flow_seconds += seconds(c2, Clock::now());
      } else {
        report.mesh_seconds += seconds(c1, Clock::now());
        const mesh::QualitySummary q = mesh::summarize_quality(mesh_, x_);
        if (q.inverted > 0) {
          const Vec3 c = mesh::vertex_centroid(mesh_, q.worst_cell, x_);
          throw SolverError(
              fmt::format("t = {:.6g} s: the mesh motion inverts fluid element {} at ({:.4g}, {:.4g}, {:.4g}) m; "
                          "the shell moves too far for this mesh: refine the fluid or space mesh near the "
                          "panel or change the motion's IDW exponents",
                          t, q.worst_cell, c.x(), c.y(), c.z()));
        }
      }
      time_ = t;
    }
    // The mesh velocity of the run is the one the flow took.
    if (flow_ && !options_.interpolated_mesh_velocity && n > 0) {
      const auto w = flow_->mesh_velocity();
      w_.assign(w.begin(), w.end());
    }
  } catch (const SolverError&) {
    if (flow_) flow_->restore(*start);
    mover_->update(t0, x_, w_);
    time_ = t0;
    throw;
  }
  return report;
}

void FlowModel::pressure_rise(const Eigen::VectorXd&, const Eigen::VectorXd&, std::span<double> dp) {
  if (!flow_) {
    std::fill(dp.begin(), dp.end(), 0.0);
    return;
  }
  flow_->pressures(loads_.fluid_nodes, node_pressure_);
  for (double& p : node_pressure_) p -= options_.reference_pressure;
  transfer_to_load_points(loads_, node_pressure_, dp);
}

void FlowModel::shear(std::span<Vec3> out) {
  if (!has_shear_) {
    std::fill(out.begin(), out.end(), Vec3::Zero());
    return;
  }
  flow_->wall_shear(wall_.group, wall_shear_);
  for (std::size_t k = 0; k < out.size(); ++k) {
    Vec3 t = Vec3::Zero();
    for (std::size_t j = 0; j < 3; ++j)
      t += loads_.weights[k][j] * wall_shear_[shear_slot_[std::size_t(loads_.slots[k][j])]];
    out[k] = t;
  }
}

void FlowModel::save(ArchiveWriter& out) const {
  out.put(time_);
  out.put(x_);
  out.put(w_);
  mover_->save(out);
  out.put(flow_ != nullptr);
  if (flow_) flow_->save(out);
}

void FlowModel::restore(ArchiveReader& in) {
  const double time = in.get<double>();
  std::vector<Vec3> x = in.get_vec3s(), w = in.get_vec3s();
  in.expect_size("the fluid mesh's positions", x.size(), x_.size());
  in.expect_size("the fluid mesh's velocities", w.size(), w_.size());
  mover_->restore(in);
  if (in.get<bool>() != (flow_ != nullptr))
    throw Error(in.what() + ": the checkpoint is of a run " + (flow_ ? "without" : "with") + " a flow");
  if (flow_) flow_->restore(in);
  time_ = time;
  x_ = std::move(x);
  w_ = std::move(w);
}

std::optional<Vec3> FlowModel::fluid_side_force() const {
  if (!flow_) return std::nullopt;
  const auto x = flow_->positions();
  const std::vector<Vec3>& shear = wall_shear_;  // of the last exchange (shear())
  const auto slot = [&](Index node) {
    return std::size_t(std::lower_bound(wall_.nodes.begin(), wall_.nodes.end(), node) - wall_.nodes.begin());
  };
  Vec3 force = Vec3::Zero();
  for (const WetFace& f : faces_) {
    const Vec3& a = x[std::size_t(f.nodes[0])];
    const Vec3 area = 0.5 * (x[std::size_t(f.nodes[1])] - a).cross(x[std::size_t(f.nodes[2])] - a);
    double p = 0.0;
    Vec3 t = Vec3::Zero();
    for (const Index i : f.nodes) {
      p += flow_->pressure(i) - options_.reference_pressure;
      if (has_shear_) t += shear[slot(i)];
    }
    force += (p / 3.0) * area + (area.norm() / 3.0) * t;
  }
  return force;
}

}  // namespace shellflow::coupling
