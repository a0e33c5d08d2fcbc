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

void FlowModel::set_distribution(Distribution distribution) {
  if (!flow_) throw InputError("coupling: a run without a flow has nothing to distribute");
  if (has_shear_)
    throw InputError(
        fmt::format("coupling: the no-slip wet wall '{}' passes viscous shear, which does not run on "
                    "several MPI ranks yet (docs/parallel.md); run it without mpirun",
                    wall_.group));
  dist_ = std::move(distribution);
  local_of_whole_.assign(x_.size(), -1);
  for (std::size_t i = 0; i < dist_->whole_of_local.size(); ++i)
    local_of_whole_[std::size_t(dist_->whole_of_local[i])] = Index(i);
  local_wall_slot_.clear();
  for (const Index l : flow_->mesh().group(wall_.group).nodes) {
    const Index whole = dist_->whole_of_local[std::size_t(l)];
    const auto it = std::lower_bound(wall_.nodes.begin(), wall_.nodes.end(), whole);
    if (it == wall_.nodes.end() || *it != whole)
      throw Error(fmt::format("coupling: node {} of this rank's wet group '{}' is not a wet node of the whole mesh", l,
                              wall_.group));
    local_wall_slot_.push_back(std::size_t(it - wall_.nodes.begin()));
  }
  local_x_.resize(dist_->whole_of_local.size());
  local_w_.resize(dist_->whole_of_local.size());
  local_wall_velocity_.resize(local_wall_slot_.size());
}

void FlowModel::gather_pressures(std::span<const Index> nodes, std::span<double> out) const {
  std::vector<int> owners(nodes.size());
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    owners[k] = dist_->owner[std::size_t(nodes[k])];
    out[k] = owners[k] == dist_->rank ? flow_->pressure(local_of_whole_[std::size_t(nodes[k])]) : 0.0;
  }
  dist_->gather(owners, out);
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
  std::vector<Vec3> x_before;  // distributed: the positions before the sub-step (its w = Δx/Δt)
  try {
    for (int m = 1; m <= n; ++m) {
      const double t = m == n ? t_end : t0 + dt * (static_cast<double>(m) / n);
      const auto c1 = Clock::now();
      // With w = Δx/Δt the mover's velocities are not needed: positions only.
      const bool positions_only = flow_ && !options_.interpolated_mesh_velocity;
      if (dist_ && positions_only) x_before.assign(x_.begin(), x_.end());
      mover_->update(t, x_, positions_only ? std::span<Vec3>{} : std::span<Vec3>(w_));
      if (flow_ && dist_) {
        // The rank's nodes of the whole motion; w = Δx/Δt as the flow forms it.
        motion.evaluate(wall_handle_, t, wall_displacement_, wall_velocity_);
        for (std::size_t j = 0; j < local_wall_slot_.size(); ++j)
          local_wall_velocity_[j] = wall_velocity_[local_wall_slot_[j]];
        flow_->set_wall_velocity(wall_.group, local_wall_velocity_);
        for (std::size_t i = 0; i < local_x_.size(); ++i) {
          local_x_[i] = x_[std::size_t(dist_->whole_of_local[i])];
          if (options_.interpolated_mesh_velocity) local_w_[i] = w_[std::size_t(dist_->whole_of_local[i])];
        }
        const auto c2 = Clock::now();
        report.mesh_seconds += seconds(c1, c2);
        const double step = t - flow_->time();
        flow_->step(step, local_x_,
                    options_.interpolated_mesh_velocity ? std::span<const Vec3>(local_w_) : std::span<const Vec3>{});
        if (!options_.interpolated_mesh_velocity)
          for (std::size_t a = 0; a < x_.size(); ++a) w_[a] = Vec3((x_[a] - x_before[a]) / step);
        report.flow_seconds += seconds(c2, Clock::now());
      } else if (flow_) {
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
    // The mesh velocity of the run is the one the flow took (on ranks: formed above, whole).
    if (flow_ && !dist_ && !options_.interpolated_mesh_velocity && n > 0) {
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
  if (dist_)
    gather_pressures(loads_.fluid_nodes, node_pressure_);
  else
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

void FlowModel::save_state(ArchiveWriter& out, bool whole) const {
  out.put(time_);
  out.put(x_);
  out.put(w_);
  mover_->save(out);
  out.put(flow_ != nullptr);
  if (flow_ && dist_ && whole)
    dist_->save_flow(out);
  else if (flow_)
    flow_->save(out);
}

void FlowModel::restore_state(ArchiveReader& in, bool whole) {
  const double time = in.get<double>();
  std::vector<Vec3> x = in.get_vec3s(), w = in.get_vec3s();
  in.expect_size("the fluid mesh's positions", x.size(), x_.size());
  in.expect_size("the fluid mesh's velocities", w.size(), w_.size());
  mover_->restore(in);
  if (in.get<bool>() != (flow_ != nullptr))
    throw Error(in.what() + ": the checkpoint is of a run " + (flow_ ? "without" : "with") + " a flow");
  if (flow_ && dist_ && whole)
    dist_->restore_flow(in);
  else if (flow_)
    flow_->restore(in);
  time_ = time;
  x_ = std::move(x);
  w_ = std::move(w);
}

std::optional<Vec3> FlowModel::fluid_side_force() const {
  if (!flow_) return std::nullopt;
  const std::span<const Vec3> x = dist_ ? std::span<const Vec3>(x_) : flow_->positions();  // the same positions
  const std::vector<Vec3>& shear = wall_shear_;  // of the last exchange (shear())
  const auto slot = [&](Index node) {
    return std::size_t(std::lower_bound(wall_.nodes.begin(), wall_.nodes.end(), node) - wall_.nodes.begin());
  };
  std::vector<double> wall_pressure;  // distributed: at wall_.nodes, from their owners
  if (dist_) {
    wall_pressure.resize(wall_.nodes.size());
    gather_pressures(wall_.nodes, wall_pressure);
  }
  const auto pressure = [&](Index node) { return dist_ ? wall_pressure[slot(node)] : flow_->pressure(node); };
  Vec3 force = Vec3::Zero();
  for (const WetFace& f : faces_) {
    const Vec3& a = x[std::size_t(f.nodes[0])];
    const Vec3 area = 0.5 * (x[std::size_t(f.nodes[1])] - a).cross(x[std::size_t(f.nodes[2])] - a);
    double p = 0.0;
    Vec3 t = Vec3::Zero();
    for (const Index i : f.nodes) {
      p += pressure(i) - options_.reference_pressure;
      if (has_shear_) t += shear[slot(i)];
    }
    force += (p / 3.0) * area + (area.norm() / 3.0) * t;
  }
  return force;
}

}  // namespace shellflow::coupling
