// Imposing the boundary conditions on the nodal values (fluid.md §9), and the per-node wall
// velocities set from outside. The node classes and normals are in boundary.cpp.
#include <fmt/format.h>

#include <cmath>

#include "shellflow/core/error.h"
#include "shellflow/core/parallel.h"
#include "shellflow/fluid/boundary.h"

namespace shellflow::fluid {
namespace {

/// Boundary passes are cheap per node: worth two threads from a few thousand nodes.
constexpr std::size_t boundary_parallel_threshold = 2048;
constexpr Index kBoundaryGrain = 1024;

}  // namespace

void BoundarySet::set_wall_velocity(std::string_view group, std::span<const Vec3> velocity) {
  std::size_t c = 0;
  while (c < conditions_.size() && conditions_[c].group != group) ++c;
  if (c == conditions_.size()) {
    std::string known;
    for (const auto& bc : conditions_) known += (known.empty() ? "'" : ", '") + bc.group + "'";
    throw InputError(
        fmt::format("fluid wall velocity for group '{}': no boundary condition on "
                    "that group; groups with conditions: {}",
                    group, known));
  }
  const auto kind = conditions_[c].kind;
  if (kind != BoundaryKind::slip_wall && kind != BoundaryKind::no_slip_wall)
    throw InputError(
        fmt::format("fluid wall velocity for group '{}': the group is a {} "
                    "boundary; wall velocities are for slip_wall and no_slip_wall "
                    "groups only",
                    group, to_string(kind)));
  if (velocity.size() != std::size_t(group_size_[c]))
    throw InputError(
        fmt::format("fluid wall velocity for group '{}' ({}): {} velocities for the "
                    "group's {} nodes; give one per node, in the group's node order",
                    group, to_string(kind), velocity.size(), group_size_[c]));
  set_velocity_[c].assign(velocity.begin(), velocity.end());
}

void BoundarySet::restore_wall_velocities(const std::vector<std::vector<Vec3>>& v) {
  if (v.size() != set_velocity_.size())
    throw InputError(fmt::format("fluid wall velocities for {} conditions, the boundary set has {}", v.size(),
                                 set_velocity_.size()));
  for (std::size_t c = 0; c < v.size(); ++c)
    if (!v[c].empty() && v[c].size() != std::size_t(group_size_[c]))
      throw InputError(fmt::format("fluid wall velocities of group '{}': {} for {} nodes", conditions_[c].group,
                                   v[c].size(), group_size_[c]));
  for (std::size_t c = 0; c < v.size(); ++c) set_velocity_[c].assign(v[c].begin(), v[c].end());
}

Vec3 BoundarySet::slip_velocity(std::size_t s, Index a, const Vec3& x, double t) const {
  // The last slip-wall group of the node with a velocity (set per node, else its closure).
  for (Index k = wall_slip_offsets_[s + 1]; k-- > wall_slip_offsets_[s];) {
    const GroupSlot& g = wall_slip_groups_[std::size_t(k)];
    const auto& set = set_velocity_[std::size_t(g.condition)];
    if (!set.empty()) return set[std::size_t(g.index)];
    const auto& bc = conditions_[std::size_t(g.condition)];
    if (bc.wall_velocity) return bc.wall_velocity(a, x, t);
  }
  return Vec3::Zero();
}

Vec3 BoundarySet::no_slip_velocity(std::size_t s, Index a, const Vec3& x, double t) const {
  const auto c = std::size_t(no_slip_condition_[s]);
  if (const auto& set = set_velocity_[c]; !set.empty()) return set[std::size_t(no_slip_index_[s])];
  const auto& bc = conditions_[c];
  return bc.wall_velocity ? bc.wall_velocity(a, x, t) : Vec3(Vec3::Zero());
}

void BoundarySet::impose_dirichlet_increments(const IdealGas& gas, double t, std::span<const Vec3> x,
                                              const FluidState& u_old, FluidState& increment) const {
  for (const auto& [a, c] : inflow_nodes_) {
    const auto& bc = conditions_[std::size_t(c)];
    const Conservative q = to_conservative(gas, bc.state_at ? bc.state_at(x[std::size_t(a)], t) : bc.state);
    const Conservative old = u_old.get(a);
    increment.set(a, {q.rho - old.rho, q.momentum - old.momentum, q.energy - old.energy});
  }
  // No-slip walls: the wall reaction must not spread through the consistent mass.
  for (std::size_t s = 0; s < no_slip_nodes_.size(); ++s) {
    const Index a = no_slip_nodes_[s];
    const auto& bc = conditions_[std::size_t(no_slip_condition_[s])];
    const Vec3 wall_velocity = no_slip_velocity(s, a, x[std::size_t(a)], t);
    const Conservative old = u_old.get(a);
    Conservative d = increment.get(a);
    const double rho = old.rho + d.rho;
    d.momentum = rho * wall_velocity - old.momentum;
    if (bc.wall_temperature)
      d.energy = rho * (gas.cv() * *bc.wall_temperature + 0.5 * wall_velocity.squaredNorm()) - old.energy;
    increment.set(a, d);
  }
}

void BoundarySet::add_weak_wall_flux(const IdealGas& gas, double t, double dt, std::span<const Vec3> x,
                                     const FluidState& u, FluidState& r) const {
  // Serial: faces share nodes, and wall-velocity closures run on the calling thread.
  for (const BoundaryFace& f : slip_wall_faces_) {
    const Vec3 area = face_area_vector(x, f);
    const double a_f = area.norm();
    const Vec3 n = area / a_f;
    std::array<std::array<double, num_variables>, 3> g{};
    for (int k = 0; k < 3; ++k) {
      const Index a = f.nodes[std::size_t(k)];
      const Index s = wall_slot_[std::size_t(a)];
      if (s < 0) continue;  // an inflow or no-slip node: its values are imposed
      const Conservative q = u.get(a);
      const double p = gas.pressure(q.rho, q.momentum.x(), q.momentum.y(), q.momentum.z(), q.energy);
      const Vec3 vel = q.momentum / q.rho;
      const double vn = vel.dot(n);
      const double wn = slip_velocity(std::size_t(s), a, x[std::size_t(a)], t).dot(n);
      // F(U).n - F(U*).n: U* has the normal velocity wn, the same rho, tangential velocity and p.
      const Vec3 m_star = q.momentum + q.rho * (wn - vn) * n;
      const double e_star = p / (gas.gamma - 1.0) + 0.5 * m_star.squaredNorm() / q.rho;
      g[std::size_t(k)][0] = q.rho * (vn - wn);
      for (int j = 0; j < 3; ++j) g[std::size_t(k)][std::size_t(1 + j)] = q.momentum[j] * vn - m_star[j] * wn;
      g[std::size_t(k)][4] = (q.energy + p) * vn - (e_star + p) * wn;
    }
    for (int k = 0; k < 3; ++k) {
      const Index a = f.nodes[std::size_t(k)];
      if (wall_slot_[std::size_t(a)] < 0) continue;
      for (int v = 0; v < num_variables; ++v) {
        const double integral = a_f / 12.0 *
                                (2.0 * g[std::size_t(k)][std::size_t(v)] + g[std::size_t((k + 1) % 3)][std::size_t(v)] +
                                 g[std::size_t((k + 2) % 3)][std::size_t(v)]);
        r.var[std::size_t(v)][std::size_t(a)] += dt * integral;
      }
    }
  }
}

void BoundarySet::apply_far_field(const IdealGas& gas, double t, std::span<const Vec3> x, std::span<const Vec3> w,
                                  std::size_t s, FluidState& u) const {
  const double gm1 = gas.gamma - 1.0;
  const Index a = far_nodes_[s];
  const Vec3& n = far_normals_[s];
  const auto& bc = conditions_[std::size_t(far_condition_[s])];
  const Primitive inf = bc.state_at ? bc.state_at(x[std::size_t(a)], t) : bc.state;
  const Primitive in = to_primitive(gas, u.get(a));
  const Vec3& wa = w[std::size_t(a)];
  const double c_in = gas.sound_speed(in.rho, in.pressure);
  const double vn = (in.velocity - wa).dot(n);
  if (vn >= c_in) return;  // supersonic outflow: nothing imposed
  if (vn <= -c_in) {
    u.set(a, to_conservative(gas, inf));
    return;
  }
  const double c_inf = gas.sound_speed(inf.rho, inf.pressure);
  const double r_plus = vn + 2.0 * c_in / gm1;
  const double r_minus = (inf.velocity - wa).dot(n) - 2.0 * c_inf / gm1;
  const double vn_b = 0.5 * (r_plus + r_minus);
  const double c_b = 0.25 * gm1 * (r_plus - r_minus);
  const Primitive& source = vn_b < 0.0 ? inf : in;
  const double entropy = source.pressure / std::pow(source.rho, gas.gamma);
  const Vec3 tangential = source.velocity - source.velocity.dot(n) * n;
  Primitive b;
  b.rho = std::pow(c_b * c_b / (gas.gamma * entropy), 1.0 / gm1);
  b.pressure = b.rho * c_b * c_b / gas.gamma;
  b.velocity = tangential + (vn_b + wa.dot(n)) * n;
  u.set(a, to_conservative(gas, b));
}

Conservative BoundarySet::wall_projection(const IdealGas& gas, double t, std::span<const Vec3> x, std::size_t s,
                                          Conservative q) const {
  const Index a = wall_nodes_[s];
  const double p = gas.pressure(q.rho, q.momentum.x(), q.momentum.y(), q.momentum.z(), q.energy);
  // Symmetry normals: u . n = 0; slip-wall normals (orthogonal to them): (u - v_wall) . n = 0.
  const Vec3 velocity = q.momentum / q.rho;
  const Vec3 relative = velocity - slip_velocity(s, a, x[std::size_t(a)], t);
  const int m_sym = wall_num_sym_normals_[s];
  const int m = weak_walls_ ? m_sym : wall_num_normals_[s];
  for (int i = 0; i < m; ++i) {
    const Vec3& n = wall_normals_[s][std::size_t(i)];
    const Vec3& r = i < m_sym ? velocity : relative;
    q.momentum -= q.rho * r.dot(n) * n;
  }
  q.energy = p / (gas.gamma - 1.0) + 0.5 * q.momentum.squaredNorm() / q.rho;
  return q;
}

template <class F>
void BoundarySet::for_each_wall_node(const F& f) const {
  // Closures may not be safe to call from several threads: with one, the pass runs serially.
  bool closures = false;
  for (std::size_t c = 0; c < conditions_.size(); ++c) {
    const auto& bc = conditions_[c];
    closures = closures || (bc.kind == BoundaryKind::slip_wall && bc.wall_velocity && set_velocity_[c].empty());
  }
  const auto nw = Index(wall_nodes_.size());
  parallel::for_range(
      nw, parallel::grain_if(!closures && std::size_t(nw) > boundary_parallel_threshold, kBoundaryGrain, nw),
      [&](Index begin, Index end) {
        for (Index s = begin; s < end; ++s) f(std::size_t(s), wall_nodes_[std::size_t(s)]);
      });
}

void BoundarySet::impose_wall_increments(const IdealGas& gas, double t, std::span<const Vec3> x,
                                         const FluidState& u_old, FluidState& increment) const {
  for_each_wall_node([&](std::size_t s, Index a) {
    const Conservative old = u_old.get(a), d = increment.get(a);
    const Conservative q =
        wall_projection(gas, t, x, s, {old.rho + d.rho, old.momentum + d.momentum, old.energy + d.energy});
    increment.set(a, {d.rho, q.momentum - old.momentum, q.energy - old.energy});  // rho is free
  });
}

void BoundarySet::apply(const IdealGas& gas, double t, std::span<const Vec3> x, std::span<const Vec3> w, FluidState& u,
                        bool initial_state) const {
  const double gm1 = gas.gamma - 1.0;
  for (const auto& [a, c] : inflow_nodes_) {
    const auto& bc = conditions_[std::size_t(c)];
    u.set(a, to_conservative(gas, bc.state_at ? bc.state_at(x[std::size_t(a)], t) : bc.state));
  }

  // Closures may not be safe to call from several threads: passes that call them run serially.
  bool far_closures = false;
  for (const auto& bc : conditions_) far_closures = far_closures || (bc.kind == BoundaryKind::far_field && bc.state_at);
  // Far field first: on slabs its nodes may be symmetry or wall nodes too, whose normal
  // components the wall pass below then removes.
  const auto nf = std::ptrdiff_t(far_nodes_.size());
  // Closures (user expressions) run on the calling thread.
  parallel::for_range(
      Index(nf),
      parallel::grain_if(!far_closures && std::size_t(nf) > boundary_parallel_threshold, kBoundaryGrain, Index(nf)),
      [&](Index begin, Index end) {
        for (Index s = begin; s < end; ++s) apply_far_field(gas, t, x, w, std::size_t(s), u);
      });

  // No-slip: u = u_wall. Isothermal walls reset rho E with the wall temperature and the
  // current rho. Adiabatic walls keep the updated total energy: that is the explicit step of
  // the semi-discrete system in which the wall momentum is constrained and the energy row
  // (with the wall's shear work) evolves freely. Keeping the pressure instead would subtract
  // the kinetic energy of the wall reaction m* - rho u_wall every step: the shear work at a
  // moving wall, and an O(dt / h^2) sink at a fixed one (first-order error in T, measured).
  // The initial state keeps its pressure (its velocity need not match the wall's).
  for (std::size_t s = 0; s < no_slip_nodes_.size(); ++s) {
    const Index a = no_slip_nodes_[s];
    const auto& bc = conditions_[std::size_t(no_slip_condition_[s])];
    Conservative q = u.get(a);
    const Vec3 wall_velocity = no_slip_velocity(s, a, x[std::size_t(a)], t);
    const double kinetic = 0.5 * q.rho * wall_velocity.squaredNorm();
    if (bc.wall_temperature)
      q.energy = q.rho * gas.cv() * *bc.wall_temperature + kinetic;
    else if (initial_state)
      q.energy = gas.pressure(q.rho, q.momentum.x(), q.momentum.y(), q.momentum.z(), q.energy) / gm1 + kinetic;
    q.momentum = q.rho * wall_velocity;
    u.set(a, q);
  }

  for_each_wall_node([&](std::size_t s, Index a) { u.set(a, wall_projection(gas, t, x, s, u.get(a))); });
}

}  // namespace shellflow::fluid
