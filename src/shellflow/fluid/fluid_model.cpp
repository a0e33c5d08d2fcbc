#include "shellflow/fluid/fluid_model.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "shellflow/core/error.h"
#include "shellflow/fluid/mass.h"
#include "shellflow/fluid/snapshot_io.h"
#include "shellflow/fluid/time_step.h"
#include "shellflow/fluid/viscous.h"

namespace shellflow::fluid {

FluidModel::FluidModel(mesh::Mesh mesh, FluidOptions options, std::vector<BoundaryCondition> conditions,
                       std::optional<CellColouring> colouring)
    : mesh_(std::move(mesh)), options_(options) {
  if (mesh_.cells.type != mesh::ElementType::tet4)
    throw InputError(
        fmt::format("fluid mesh '{}' ({}) has {} cells; the fluid solver needs "
                    "4-node tetrahedra (Mesh.ElementOrder = 1)",
                    mesh_.name, mesh_.source, mesh::element_info(mesh_.cells.type).short_name));
  const Index nn = mesh_.num_nodes();
  if (colouring && colouring->order.size() != std::size_t(mesh_.num_cells()))
    throw InputError(fmt::format("fluid mesh '{}': the given colouring orders {} cells, the mesh has {}", mesh_.name,
                                 colouring->order.size(), mesh_.num_cells()));
  colours_ = colouring ? std::move(*colouring)
                       : colour_cells(mesh_.cells.connectivity, 4, nn, default_block_size(mesh_.num_cells()));
  tets_.reserve(mesh_.cells.connectivity.size());
  for (const Index c : colours_.order) {
    const auto cell = mesh_.cells.element(c);
    tets_.insert(tets_.end(), cell.begin(), cell.end());
  }
  x_ = mesh_.nodes;
  w_.assign(std::size_t(nn), Vec3::Zero());
  compute_geometry(x_, tets_, geometry_);
  check_viscosity(options_.gas);
  boundaries_ = BoundarySet(mesh_, tets_, options_.gas, std::move(conditions));
  boundaries_.set_weak_walls(options_.weak_slip_walls);
  boundaries_.update_normals(x_);
  state_.resize(nn);
  residual_.resize(nn);
  next_state_.resize(nn);
}

void FluidModel::set_state(const std::function<Primitive(const Vec3&)>& field) {
  for (Index a = 0; a < mesh_.num_nodes(); ++a) state_.set(a, to_conservative(options_.gas, field(x_[std::size_t(a)])));
  boundaries_.apply(options_.gas, time_, x_, w_, state_, true);
  exchange(state_);
  check_positivity(state_, time_);
  viscosity_valid_ = false;
}

void FluidModel::exchange(FluidState& u) {
  if (!distribution_.exchange) return;
  double* fields[num_variables];
  for (int v = 0; v < num_variables; ++v) fields[v] = u.var[std::size_t(v)].data();
  distribution_.exchange(fields);
}

void FluidModel::set_state(const FluidState& state) {
  if (state.size() != mesh_.num_nodes())
    throw InputError(
        fmt::format("fluid state has {} nodes, mesh '{}' has {}", state.size(), mesh_.name, mesh_.num_nodes()));
  state_ = state;
  exchange(state_);
  viscosity_valid_ = false;
}

void FluidModel::set_mesh_velocity(std::span<const Vec3> w) {
  if (w.size() != x_.size())
    throw InputError(fmt::format("fluid mesh velocity has {} entries for {} nodes", w.size(), x_.size()));
  w_.assign(w.begin(), w.end());
}

void FluidModel::set_wall_velocity(std::string_view group, std::span<const Vec3> velocity) {
  boundaries_.set_wall_velocity(group, velocity);
}

void FluidModel::pressures(std::span<const Index> nodes, std::span<double> out) const {
  if (nodes.size() != out.size())
    throw InputError(fmt::format("fluid pressures: {} nodes but room for {} values", nodes.size(), out.size()));
  for (std::size_t k = 0; k < nodes.size(); ++k) out[k] = pressure(nodes[k]);
}

FluidSnapshot FluidModel::snapshot() const {
  return {state_, x_, w_, time_, steps_, boundaries_.set_wall_velocities(), density_rate_};
}

void FluidModel::restore(const FluidSnapshot& s) {
  const auto nn = std::size_t(mesh_.num_nodes());
  bool sizes = s.x.size() == nn && s.w.size() == nn;
  for (const auto& v : s.U.var) sizes = sizes && v.size() == nn;
  if (!sizes)
    throw InputError(
        fmt::format("fluid snapshot with {} states, {} positions and {} velocities "
                    "for mesh '{}' of {} nodes",
                    s.U.size(), s.x.size(), s.w.size(), mesh_.name, nn));
  compute_geometry(s.x, loop(), next_geometry_);  // throws before anything changes
  boundaries_.restore_wall_velocities(s.wall_velocity);
  std::swap(geometry_, next_geometry_);
  state_ = s.U;
  x_ = s.x;
  w_ = s.w;
  boundaries_.update_normals(x_);
  time_ = s.time;
  steps_ = s.steps;
  density_rate_ = s.density_rate;
  viscosity_valid_ = false;
}

void FluidModel::save(ArchiveWriter& out) const { write_snapshot(*this, out); }

void FluidModel::restore(ArchiveReader& in) { read_snapshot(*this, in); }

void FluidModel::check_cfl(double cfl) const {
  // Measured on tetrahedra (tests/fluid/test_stability.cpp): stable to 0.9 at rest, unstable
  // at 1.0 with lumped mass; the consistent mass lowers the limit to about 0.6x (spec §5).
  const double limit = options_.consistent_mass_iterations > 0 ? 0.6 : 1.0;
  if (!(cfl > 0.0) || cfl > limit)
    throw InputError(
        fmt::format("fluid CFL number {} is outside (0, {}]: the explicit step is unstable above it "
                    "({} mass); use 0.5 (lumped) or 0.3 (consistent)",
                    cfl, limit, options_.consistent_mass_iterations > 0 ? "consistent" : "lumped"));
}

void FluidModel::update_viscosity() {
  if (viscosity_valid_) return;
  compute_artificial_viscosity(options_.gas, options_.q_dif, options_.av_smoothing, loop(), geometry_, state_, av_work_,
                               viscosity_, distribution_.exchange);
  viscosity_valid_ = true;
}

double FluidModel::stable_dt(double cfl) {
  check_cfl(cfl);
  update_viscosity();
  const double dt =
      min_element_time_step(options_.gas, tets_, geometry_, state_, w_, time_step_diffusivity(), time_step_work_);
  return cfl * (distribution_.min ? distribution_.min(dt) : dt);
}

void FluidModel::set_distribution(Distribution distribution) {
  if (options_.consistent_mass_iterations > 0)
    throw InputError("a distributed flow has lumped mass only (fluid.consistent_mass_iterations = 0)");
  if (!distribution.exchange || !distribution.min || !distribution.sum || !distribution.first_error ||
      distribution.owned < 0 || distribution.owned > mesh_.num_nodes())
    throw InputError(
        fmt::format("fluid mesh '{}': a distribution needs exchange, min, sum, first_error and 0 <= owned "
                    "<= {} nodes",
                    mesh_.name, mesh_.num_nodes()));
  distribution_ = std::move(distribution);
  exchange(state_);  // the ghosts' boundary conditions used the rank's partial wall normals
  viscosity_valid_ = false;
}

std::span<const double> FluidModel::time_step_diffusivity() {
  if (!options_.gas.viscous()) return viscosity_;
  element_diffusivity(options_.gas, tets_, state_, viscosity_, diffusivity_);
  return diffusivity_;
}

void FluidModel::step(double dt) { step(dt, x_, std::span<const Vec3>{}); }

void FluidModel::step(double dt, std::span<const Vec3> x_next, std::span<const Vec3> w) {
  advance(dt, x_next, w, false);
}

void FluidModel::step_local(double cfl) {
  check_cfl(cfl);
  update_viscosity();
  double dt_min = cfl * min_element_time_step(options_.gas, tets_, geometry_, state_, w_, time_step_diffusivity(),
                                              time_step_work_, &element_dt_);
  if (distribution_.min) dt_min = distribution_.min(dt_min);
  for (auto& dt : element_dt_) dt *= cfl;
  nodal_dt_.assign(std::size_t(mesh_.num_nodes()), std::numeric_limits<double>::infinity());
  for (std::size_t e = 0; e < element_dt_.size(); ++e)
    for (int a = 0; a < 4; ++a) {
      double& d = nodal_dt_[std::size_t(tets_[4 * e + std::size_t(a)])];
      d = std::min(d, element_dt_[e]);
    }
  if (distribution_.exchange) {  // a ghost's minimum misses the cells beyond the ghost layer
    double* field = nodal_dt_.data();
    distribution_.exchange(std::span<double* const>(&field, 1));
  }
  w_.assign(w_.size(), Vec3::Zero());  // steady runs: fixed mesh
  advance(dt_min, x_, {}, true);
}

// One step in stages (fluid.md §7): the mesh velocity, the artificial viscosity, the residual,
// the mass inverse, then the new state's geometry and boundary conditions, its ghosts'
// exchange, its checks, the monitor, and the commit. A failed step leaves the model as it was.
void FluidModel::advance(double dt, std::span<const Vec3> x_next, std::span<const Vec3> w, bool local) {
  check_step_input(dt, x_next, w);
  const bool moves = x_next.data() != x_.data();
  StepClock clock;
  const bool mesh_moves = step_mesh_velocity(dt, x_next, w);
  clock.lap(timings_.mesh_velocity);
  update_viscosity();
  clock.lap(timings_.viscosity);
  ResidualParameters p{options_.gas, dt, options_.tg_velocity, options_.moving_mesh_correction, mesh_moves, {}, {}};
  if (local) {
    p.element_dt = element_dt_;
    p.nodal_dt = nodal_dt_;
  }
  assemble_step_residual(p, w_next_);
  clock.lap(timings_.element_pass);
  const double t_next = time_ + dt;
  apply_mass_inverse(residual_, t_next, x_next, state_, next_state_);
  clock.lap(timings_.update);
  bool normals_moved = false;
  std::string failure = moves ? move_geometry(x_next, normals_moved, clock) : std::string();
  if (failure.empty()) boundaries_.apply(options_.gas, t_next, x_next, w_next_, next_state_);
  exchange(next_state_);
  clock.lap(timings_.boundary);
  check_next_state(t_next, std::move(failure), normals_moved);
  density_rate_ = step_density_rate(dt, local);
  commit_step(t_next, x_next, moves);
  clock.lap(timings_.checks);
  ++timings_.steps;
}

void FluidModel::StepClock::lap(double& part) {
  const auto now = std::chrono::steady_clock::now();
  part += std::chrono::duration<double>(now - last).count();
  last = now;
}

void FluidModel::check_step_input(double dt, std::span<const Vec3> x_next, std::span<const Vec3> w) const {
  const Index nn = mesh_.num_nodes();
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw SolverError(fmt::format("fluid time step {} at t = {} is not positive", dt, time_));
  if (x_next.size() != std::size_t(nn) || (!w.empty() && w.size() != std::size_t(nn)))
    throw InputError(
        fmt::format("fluid mesh motion: {} positions and {} velocities for {} "
                    "nodes",
                    x_next.size(), w.size(), nn));
}

bool FluidModel::step_mesh_velocity(double dt, std::span<const Vec3> x_next, std::span<const Vec3> w) {
  // A member: no allocation per step once sized.
  const Index nn = mesh_.num_nodes();
  w_next_.resize(std::size_t(nn));
  const bool moves_here = reduce_items(
      nn, parallel::kNodeGrain, node_parallel_threshold, false,
      [&](Index a) {
        const auto i = std::size_t(a);
        const Vec3 v = !w.empty() ? w[i] : Vec3((x_next[i] - x_[i]) / dt);
        w_next_[i] = v;
        return v.x() != 0.0 || v.y() != 0.0 || v.z() != 0.0;
      },
      [](bool p, bool q) { return p || q; });
  // Every rank takes the ALE terms if the mesh moves anywhere (the same bits on any rank count).
  return distribution_.exchange ? distribution_.min(moves_here ? 0.0 : 1.0) == 0.0 : moves_here;
}

std::string FluidModel::move_geometry(std::span<const Vec3> x_next, bool& normals_moved, StepClock& clock) {
  // On ranks the failure found on one rank is kept until the step's exchange is done, then
  // agreed on (check_next_state).
  std::string failure;
  try {
    compute_geometry(x_next, loop(), next_geometry_);  // throws before anything changes
  } catch (const SolverError& e) {
    if (!distribution_.exchange) throw;
    failure = e.what();
  }
  clock.lap(timings_.geometry);
  if (failure.empty()) {
    boundaries_.update_normals(x_next);
    normals_moved = true;
  }
  clock.lap(timings_.normals);
  return failure;
}

void FluidModel::check_next_state(double t_next, std::string failure, bool normals_moved) {
  const bool distributed = bool(distribution_.exchange);
  try {
    if (failure.empty()) check_positivity(next_state_, t_next);
  } catch (const SolverError& e) {
    if (!distributed) {
      if (normals_moved) boundaries_.update_normals(x_);
      throw;
    }
    failure = e.what();
  }
  if (distributed) failure = distribution_.first_error(failure);
  if (!failure.empty()) {
    if (normals_moved) boundaries_.update_normals(x_);
    throw SolverError(failure);
  }
}

double FluidModel::step_density_rate(double dt, bool local) {
  // Steady-state residual: RMS of d(rho)/dt over the nodes, summed in fixed chunks (the
  // same bits whatever the thread count).
  const Index nn = mesh_.num_nodes();
  const auto rate = [&](Index a) {
    return (next_state_.var[0][std::size_t(a)] - state_.var[0][std::size_t(a)]) /
           (local ? nodal_dt_[std::size_t(a)] : dt);
  };
  if (distribution_.exchange) {
    // Over the owned nodes (ghosts would count twice), the same on every rank.
    double owned2 = 0.0;
    for (Index a = 0; a < distribution_.owned; ++a) {
      const double d = rate(a);
      owned2 += d * d;
    }
    return std::sqrt(distribution_.sum(owned2) / distribution_.sum(double(distribution_.owned)));
  }
  constexpr Index chunk = 4096;
  const Index num_chunks = (nn + chunk - 1) / chunk;
  rate_sums_.resize(std::size_t(num_chunks));
  parallel::for_range(nn, parallel::grain_if(nn > node_parallel_threshold, chunk, nn), [&](Index begin, Index end) {
    // Threaded: one chunk each; serial: one call for all of them.
    for (Index b = begin / chunk; b * chunk < end; ++b) {
      double sum = 0.0;
      for (Index a = b * chunk; a < std::min(end, (b + 1) * chunk); ++a) {
        const double d = rate(a);
        sum += d * d;
      }
      rate_sums_[std::size_t(b)] = sum;
    }
  });
  double rate2 = 0.0;
  for (const double sum : rate_sums_) rate2 += sum;
  return std::sqrt(rate2 / nn);
}

void FluidModel::commit_step(double t_next, std::span<const Vec3> x_next, bool moves) {
  std::swap(state_, next_state_);
  if (moves) {
    std::swap(geometry_, next_geometry_);
    x_.assign(x_next.begin(), x_next.end());
  }
  std::swap(w_, w_next_);
  time_ = t_next;
  ++steps_;
  viscosity_valid_ = false;
}

void FluidModel::assemble_step_residual(const ResidualParameters& p, std::span<const Vec3> w_step) {
  assemble_residual(p, loop(), geometry_, state_, w_step, viscosity_, residual_);
  add_natural_boundary_term(p, loop(), x_, geometry_, state_, w_step, boundaries_.natural_faces(), residual_);
  if (boundaries_.weak_walls()) boundaries_.add_weak_wall_flux(options_.gas, time_, p.dt, x_, state_, residual_);
  if (options_.gas.viscous()) {
    add_viscous_residual(options_.gas, p.dt, p.nodal_dt, loop(), geometry_, state_, residual_, viscous_work_);
    add_wall_work(options_.gas, p.dt, p.nodal_dt, tets_, x_, geometry_, state_, boundaries_.adiabatic_wall_faces(),
                  residual_);
  }
}

void FluidModel::apply_mass_inverse(const FluidState& r, double t_end, std::span<const Vec3> x_next,
                                    const FluidState& base, FluidState& out) {
  const Index nn = mesh_.num_nodes();
  if (options_.consistent_mass_iterations > 0) {
    increment_.resize(nn);
    mass_work_.resize(nn);
    // The increments of the constrained values re-imposed after every sweep (docs/fluid.md
    // "Consistent mass"): Dirichlet (inflow, no-slip), and the slip-wall and symmetry nodes'
    // normal momentum, which would otherwise reach their neighbours during the sweeps.
    solve_consistent_mass(loop(), geometry_, r, options_.consistent_mass_iterations, increment_, mass_work_,
                          [&](FluidState& dx) {
                            boundaries_.impose_dirichlet_increments(options_.gas, t_end, x_next, base, dx);
                            boundaries_.impose_wall_increments(options_.gas, t_end, x_next, base, dx);
                          });
    for_each_node(nn, [&](Index a) {
      const auto i = std::size_t(a);
      for (int v = 0; v < num_variables; ++v)
        out.var[std::size_t(v)][i] = base.var[std::size_t(v)][i] + increment_.var[std::size_t(v)][i];
    });
  } else {
    const auto& m = geometry_.lumped_mass;
    for_each_node(nn, [&](Index a) {
      const auto i = std::size_t(a);
      for (int v = 0; v < num_variables; ++v)
        out.var[std::size_t(v)][i] = base.var[std::size_t(v)][i] + r.var[std::size_t(v)][i] / m[i];
    });
  }
}

void FluidModel::check_positivity(const FluidState& u, double t) const {
  const Index nn = u.size();
  // The highest bad node, whatever the thread count.
  const Index bad = reduce_items(
      nn, parallel::kNodeGrain, node_parallel_threshold, Index{-1},
      [&](Index a) {
        const auto i = std::size_t(a);
        const double rho = u.var[0][i];
        const double p = options_.gas.pressure(rho, u.var[1][i], u.var[2][i], u.var[3][i], u.var[4][i]);
        return !(rho > 0.0) || !(p > 0.0) || !std::isfinite(rho) || !std::isfinite(p) ? a : Index{-1};
      },
      [](Index p, Index q) { return std::max(p, q); });
  if (bad < 0) return;
  const Primitive s = to_primitive(options_.gas, u.get(bad));
  const Vec3& x = x_[std::size_t(bad)];
  throw SolverError(
      fmt::format("fluid state not physical at node {} (tag {}, x = ({:.6g}, {:.6g}, {:.6g})) at t = {:.6g}: "
                  "rho = {:.6g}, u = ({:.6g}, {:.6g}, {:.6g}), p = {:.6g}; lower the CFL number or raise "
                  "q_dif",
                  bad, mesh_.node_tags.size() > std::size_t(bad) ? mesh_.node_tags[std::size_t(bad)] : 0, x.x(), x.y(),
                  x.z(), t, s.rho, s.velocity.x(), s.velocity.y(), s.velocity.z(), s.pressure));
}

}  // namespace shellflow::fluid

namespace shellflow::fluid {
namespace {
template <class T>
std::size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}
std::size_t bytes(const FluidState& s) {
  std::size_t b = 0;
  for (const auto& v : s.var) b += bytes(v);
  return b;
}
std::size_t bytes(const TetGeometry& g) {
  return bytes(g.volume) + bytes(g.grad) + bytes(g.size) + bytes(g.lumped_mass);
}
}  // namespace

std::size_t FluidModel::memory_bytes() const {
  std::size_t b = bytes(mesh_.nodes) + bytes(mesh_.node_tags) + bytes(mesh_.cells.connectivity);
  for (const auto& g : mesh_.groups) b += bytes(g.elements.connectivity) + bytes(g.nodes) + bytes(g.cells);
  b += bytes(tets_) + bytes(colours_.order) + bytes(colours_.block_offsets) + bytes(x_) + bytes(w_) + bytes(w_next_) +
       bytes(rate_sums_);
  b += bytes(geometry_) + bytes(next_geometry_);
  b += bytes(state_) + bytes(next_state_) + bytes(residual_) + bytes(increment_) + bytes(mass_work_);
  b += bytes(av_work_.pressure) + bytes(av_work_.nodal_viscosity) + bytes(av_work_.speed);
  for (const auto& g : av_work_.gradient) b += bytes(g);
  b += bytes(viscosity_) + bytes(diffusivity_) + bytes(viscous_work_) + bytes(time_step_work_) + bytes(element_dt_) +
       bytes(nodal_dt_);
  return b;  // boundary data (surface only) not counted
}

std::vector<double> FluidModel::nodal_artificial_viscosity() {
  update_viscosity();
  const std::size_t nn = x_.size();
  std::vector<double> sum(nn, 0.0), weight(nn, 0.0);
  for (Index e = 0; e < geometry_.num_elements(); ++e) {
    const double v = geometry_.volume[std::size_t(e)];
    for (int k = 0; k < 4; ++k) {
      const auto a = std::size_t(tets_[4 * std::size_t(e) + std::size_t(k)]);
      sum[a] += v * viscosity_[std::size_t(e)];
      weight[a] += v;
    }
  }
  for (std::size_t a = 0; a < nn; ++a) sum[a] = weight[a] > 0.0 ? sum[a] / weight[a] : 0.0;
  if (distribution_.exchange) {  // a ghost's mean misses the cells beyond the ghost layer
    double* field = sum.data();
    distribution_.exchange(std::span<double* const>(&field, 1));
  }
  return sum;
}

}  // namespace shellflow::fluid
