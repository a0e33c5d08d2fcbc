#include "shellflow/fluid/boundary.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include <fmt/format.h>

#include "shellflow/core/error.h"

namespace shellflow::fluid {
namespace {

using FaceKey = std::array<Index, 3>;
FaceKey sorted_key(Index a, Index b, Index c) {
  FaceKey k{a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}

int rank(BoundaryKind k) {
  switch (k) {
    case BoundaryKind::supersonic_inflow: return 5;
    case BoundaryKind::no_slip_wall: return 4;
    case BoundaryKind::slip_wall:
    case BoundaryKind::symmetry: return 3;
    case BoundaryKind::far_field: return 2;
    case BoundaryKind::supersonic_outflow: return 1;
  }
  return 0;
}

bool is_wall(BoundaryKind k) { return k == BoundaryKind::slip_wall || k == BoundaryKind::symmetry; }

/// CSR of faces per node for the nodes in `nodes` (sorted), faces selected by `take`.
template <class Take>
void faces_per_node(const std::vector<Index>& nodes, std::span<const Index> slot_of_node,
                    std::size_t num_faces, const std::function<FaceKey(std::size_t)>& nodes_of,
                    Take&& take, std::vector<Index>& offsets, std::vector<Index>& out) {
  std::vector<std::vector<Index>> lists(nodes.size());
  for (std::size_t f = 0; f < num_faces; ++f) {
    if (!take(f)) continue;
    for (const Index a : nodes_of(f)) {
      const Index s = slot_of_node[std::size_t(a)];
      if (s >= 0) lists[std::size_t(s)].push_back(Index(f));
    }
  }
  offsets.assign(1, 0);
  out.clear();
  for (auto& l : lists) {
    out.insert(out.end(), l.begin(), l.end());
    offsets.push_back(Index(out.size()));
  }
}

}  // namespace

const char* to_string(BoundaryKind kind) {
  switch (kind) {
    case BoundaryKind::supersonic_inflow: return "supersonic_inflow";
    case BoundaryKind::supersonic_outflow: return "supersonic_outflow";
    case BoundaryKind::slip_wall: return "slip_wall";
    case BoundaryKind::symmetry: return "symmetry";
    case BoundaryKind::far_field: return "far_field";
    case BoundaryKind::no_slip_wall: return "no_slip_wall";
  }
  return "?";
}

BoundarySet::BoundarySet(const mesh::Mesh& mesh, std::span<const Index> tets,
                         const IdealGas& gas, std::vector<BoundaryCondition> conditions)
    : conditions_(std::move(conditions)) {
  const Index nn = mesh.num_nodes();
  std::map<std::string, int> by_group;
  for (std::size_t c = 0; c < conditions_.size(); ++c) {
    const auto& bc = conditions_[c];
    const auto& group = mesh.group(bc.group);  // throws InputError naming the groups
    if (group.dim != 2 || group.elements.type != mesh::ElementType::tri3)
      throw InputError(fmt::format(
          "fluid boundary condition '{}' on group '{}' of mesh '{}': the group is not a "
          "surface of 3-node triangles; give conditions on boundary surfaces only",
          to_string(bc.kind), bc.group, mesh.name));
    if (!by_group.emplace(bc.group, int(c)).second)
      throw InputError(fmt::format("fluid boundary group '{}' of mesh '{}' has two conditions; "
                                   "keep one", bc.group, mesh.name));
    if (bc.kind == BoundaryKind::supersonic_inflow) {
      // A varying state is checked at the group's first node at t = 0.
      const Primitive s = bc.state_at && !group.nodes.empty()
                              ? bc.state_at(mesh.nodes[std::size_t(group.nodes.front())], 0.0)
                              : bc.state;
      const double c0 = gas.sound_speed(s.rho, s.pressure);
      const double mach = s.velocity.norm() / c0;
      if (!(s.rho > 0.0 && s.pressure > 0.0) || !(mach >= 1.0))
        throw InputError(fmt::format(
            "fluid boundary '{}': supersonic_inflow needs a supersonic state with rho, p > 0, "
            "got rho = {}, p = {}, Mach {:.4g}; use far_field for a subsonic inflow",
            bc.group, s.rho, s.pressure, mach));
    }
    if (bc.kind == BoundaryKind::no_slip_wall && !gas.viscous())
      throw InputError(fmt::format(
          "fluid boundary '{}' of mesh '{}': no_slip_wall needs the viscous terms, but the gas "
          "is inviscid; set the fluid viscosity (fluid.gas.viscosity: constant or sutherland) "
          "or use slip_wall",
          bc.group, mesh.name));
    if (bc.wall_temperature &&
        (bc.kind != BoundaryKind::no_slip_wall || !(*bc.wall_temperature > 0.0) ||
         !std::isfinite(*bc.wall_temperature)))
      throw InputError(fmt::format(
          "fluid boundary '{}' ({}): wall temperature {} K; give a positive temperature on a "
          "no_slip_wall, or none (adiabatic wall)",
          bc.group, to_string(bc.kind), *bc.wall_temperature));
  }
  for (const auto& g : mesh.groups)
    if (g.dim == 2 && !by_group.contains(g.name))
      throw InputError(fmt::format(
          "fluid boundary group '{}' of mesh '{}' has no boundary condition; give it one of "
          "supersonic_inflow, supersonic_outflow, slip_wall, no_slip_wall, symmetry, far_field",
          g.name, mesh.name));

  // Faces with their owning element.
  auto& face_index = face_index_;
  for (std::size_t c = 0; c < conditions_.size(); ++c) {
    const auto& block = mesh.group(conditions_[c].group).elements;
    for (Index f = 0; f < block.size(); ++f) {
      const auto n = block.element(f);
      Face face;
      face.face.nodes = {n[0], n[1], n[2]};
      face.face.element = -1;
      face.condition = int(c);
      face_index.emplace(sorted_key(n[0], n[1], n[2]), faces_.size());
      faces_.push_back(face);
    }
  }
  static constexpr int tet_faces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  const std::size_t ne = tets.size() / 4;
  for (std::size_t e = 0; e < ne; ++e) {
    const Index* n = tets.data() + 4 * e;
    for (int opp = 0; opp < 4; ++opp) {
      const auto it = face_index.find(sorted_key(n[tet_faces[opp][0]], n[tet_faces[opp][1]],
                                                 n[tet_faces[opp][2]]));
      if (it == face_index.end()) continue;
      auto& f = faces_[it->second].face;
      f.element = Index(e);
      f.opposite_node = n[opp];
    }
  }
  for (const auto& f : faces_) {
    if (f.face.element < 0)
      throw InputError(fmt::format(
          "fluid boundary group '{}' of mesh '{}': triangle ({} {} {}) is not a face of any "
          "tetrahedron; regenerate the mesh with the group on the volume's boundary",
          conditions_[std::size_t(f.condition)].group, mesh.name, f.face.nodes[0],
          f.face.nodes[1], f.face.nodes[2]));
    const auto kind = conditions_[std::size_t(f.condition)].kind;
    if (kind == BoundaryKind::supersonic_outflow || kind == BoundaryKind::far_field)
      natural_faces_.push_back(f.face);
    if (kind == BoundaryKind::no_slip_wall && !conditions_[std::size_t(f.condition)].wall_temperature)
      adiabatic_wall_faces_.push_back(f.face);
  }

  // Node classification by priority.
  std::vector<int> node_rank(static_cast<std::size_t>(nn), 0);
  std::vector<int> node_condition(static_cast<std::size_t>(nn), -1);
  for (const auto& f : faces_) {
    const int r = rank(conditions_[std::size_t(f.condition)].kind);
    for (const Index a : f.face.nodes)
      if (r > node_rank[std::size_t(a)]) {
        node_rank[std::size_t(a)] = r;
        node_condition[std::size_t(a)] = f.condition;
      }
  }
  wall_slot_.assign(std::size_t(nn), -1);
  std::vector<Index> far_slot(static_cast<std::size_t>(nn), -1);
  for (Index a = 0; a < nn; ++a) {
    const int c = node_condition[std::size_t(a)];
    if (c < 0) continue;
    const auto kind = conditions_[std::size_t(c)].kind;
    if (kind == BoundaryKind::supersonic_inflow) {
      inflow_nodes_.emplace_back(a, c);
    } else if (kind == BoundaryKind::no_slip_wall) {
      no_slip_nodes_.push_back(a);
      no_slip_condition_.push_back(c);
    } else if (is_wall(kind)) {
      wall_slot_[std::size_t(a)] = Index(wall_nodes_.size());
      wall_nodes_.push_back(a);
    } else if (kind == BoundaryKind::far_field) {
      far_slot[std::size_t(a)] = Index(far_nodes_.size());
      far_nodes_.push_back(a);
      far_condition_.push_back(c);
    }
  }
  const std::function<FaceKey(std::size_t)> nodes_of = [&](std::size_t f) {
    return FaceKey{faces_[f].face.nodes};
  };
  // Wall faces: symmetry faces first so that their exact plane normal leads Gram–Schmidt.
  std::vector<Index> sym_offsets, sym_faces, slip_offsets, slip_faces;
  faces_per_node(wall_nodes_, wall_slot_, faces_.size(), nodes_of,
                 [&](std::size_t f) {
                   return conditions_[std::size_t(faces_[f].condition)].kind == BoundaryKind::symmetry;
                 },
                 sym_offsets, sym_faces);
  faces_per_node(wall_nodes_, wall_slot_, faces_.size(), nodes_of,
                 [&](std::size_t f) {
                   return conditions_[std::size_t(faces_[f].condition)].kind == BoundaryKind::slip_wall;
                 },
                 slip_offsets, slip_faces);
  wall_face_offsets_.assign(1, 0);
  wall_moving_condition_.assign(wall_nodes_.size(), -1);
  for (std::size_t s = 0; s < wall_nodes_.size(); ++s) {
    for (Index k = sym_offsets[s]; k < sym_offsets[s + 1]; ++k) wall_faces_.push_back(sym_faces[std::size_t(k)]);
    for (Index k = slip_offsets[s]; k < slip_offsets[s + 1]; ++k) {
      const Index f = slip_faces[std::size_t(k)];
      wall_faces_.push_back(f);
      if (conditions_[std::size_t(faces_[std::size_t(f)].condition)].wall_velocity)
        wall_moving_condition_[s] = faces_[std::size_t(f)].condition;
    }
    wall_face_offsets_.push_back(Index(wall_faces_.size()));
  }
  faces_per_node(far_nodes_, far_slot, faces_.size(), nodes_of,
                 [&](std::size_t f) {
                   return conditions_[std::size_t(faces_[f].condition)].kind == BoundaryKind::far_field;
                 },
                 far_face_offsets_, far_faces_);
  wall_normals_.resize(wall_nodes_.size());
  wall_num_normals_.assign(wall_nodes_.size(), 0);
  far_normals_.assign(far_nodes_.size(), Vec3::Zero());
}

void BoundarySet::update_normals(std::span<const Vec3> x) {
  std::vector<Vec3> area(faces_.size());
  for (std::size_t f = 0; f < faces_.size(); ++f) area[f] = face_area_vector(x, faces_[f].face);
  const double cos30 = std::sqrt(3.0) / 2.0;
  for (std::size_t s = 0; s < wall_nodes_.size(); ++s) {
    // Cluster the adjacent face normals; each cluster is one wall direction.
    std::array<Vec3, 8> clusters;
    int nc = 0;
    for (Index k = wall_face_offsets_[s]; k < wall_face_offsets_[s + 1]; ++k) {
      const Vec3& a = area[std::size_t(wall_faces_[std::size_t(k)])];
      const Vec3 n = a.normalized();
      int found = -1;
      for (int c = 0; c < nc && found < 0; ++c)
        if (clusters[std::size_t(c)].normalized().dot(n) > cos30) found = c;
      if (found >= 0) {
        clusters[std::size_t(found)] += a;
      } else if (nc < int(clusters.size())) {
        clusters[std::size_t(nc++)] = a;
      }
    }
    // Gram–Schmidt: the constrained subspace spanned by the distinct normals.
    int m = 0;
    auto& basis = wall_normals_[s];
    for (int c = 0; c < nc && m < 3; ++c) {
      Vec3 v = clusters[std::size_t(c)].normalized();
      for (int i = 0; i < m; ++i) v -= v.dot(basis[std::size_t(i)]) * basis[std::size_t(i)];
      const double len = v.norm();
      if (len > 1e-6) basis[std::size_t(m++)] = v / len;
    }
    wall_num_normals_[s] = m;
  }
  for (std::size_t s = 0; s < far_nodes_.size(); ++s) {
    Vec3 n = Vec3::Zero();
    for (Index k = far_face_offsets_[s]; k < far_face_offsets_[s + 1]; ++k)
      n += area[std::size_t(far_faces_[std::size_t(k)])];
    far_normals_[s] = n.normalized();
  }
}

void BoundarySet::impose_dirichlet_increments(const IdealGas& gas, double t,
                                              std::span<const Vec3> x, const FluidState& u_old,
                                              FluidState& increment) const {
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
    const Vec3 wall_velocity =
        bc.wall_velocity ? bc.wall_velocity(a, x[std::size_t(a)], t) : Vec3(Vec3::Zero());
    const Conservative old = u_old.get(a);
    Conservative d = increment.get(a);
    const double rho = old.rho + d.rho;
    d.momentum = rho * wall_velocity - old.momentum;
    if (bc.wall_temperature)
      d.energy = rho * (gas.cv() * *bc.wall_temperature + 0.5 * wall_velocity.squaredNorm()) - old.energy;
    increment.set(a, d);
  }
}

BoundaryFace BoundarySet::owner_of(Index a, Index b, Index c) const {
  const auto it = face_index_.find(sorted_key(a, b, c));
  if (it == face_index_.end())
    throw InputError(fmt::format("triangle ({} {} {}) is not a face of a fluid boundary group "
                                 "with a condition", a, b, c));
  return faces_[it->second].face;
}

std::span<const Vec3> BoundarySet::wall_constraints(Index node) const {
  const Index s = wall_slot_.empty() ? -1 : wall_slot_[std::size_t(node)];
  if (s < 0) return {};
  return {wall_normals_[std::size_t(s)].data(), std::size_t(wall_num_normals_[std::size_t(s)])};
}

void BoundarySet::apply(const IdealGas& gas, double t, std::span<const Vec3> x,
                        std::span<const Vec3> w, FluidState& u, bool initial_state) const {
  const double gm1 = gas.gamma - 1.0;
  auto state_of = [&](const BoundaryCondition& bc, Index a) {
    return bc.state_at ? bc.state_at(x[std::size_t(a)], t) : bc.state;
  };
  for (const auto& [a, c] : inflow_nodes_)
    u.set(a, to_conservative(gas, state_of(conditions_[std::size_t(c)], a)));

  for (std::size_t s = 0; s < far_nodes_.size(); ++s) {
    const Index a = far_nodes_[s];
    const Vec3& n = far_normals_[s];
    const Primitive inf = state_of(conditions_[std::size_t(far_condition_[s])], a);
    const Primitive in = to_primitive(gas, u.get(a));
    const Vec3& wa = w[std::size_t(a)];
    const double c_in = gas.sound_speed(in.rho, in.pressure);
    const double vn = (in.velocity - wa).dot(n);
    if (vn >= c_in) continue;  // supersonic outflow: nothing imposed
    if (vn <= -c_in) {
      u.set(a, to_conservative(gas, inf));
      continue;
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
    const Vec3 wall_velocity =
        bc.wall_velocity ? bc.wall_velocity(a, x[std::size_t(a)], t) : Vec3(Vec3::Zero());
    const double kinetic = 0.5 * q.rho * wall_velocity.squaredNorm();
    if (bc.wall_temperature)
      q.energy = q.rho * gas.cv() * *bc.wall_temperature + kinetic;
    else if (initial_state)
      q.energy = gas.pressure(q.rho, q.momentum.x(), q.momentum.y(), q.momentum.z(), q.energy) / gm1 +
                 kinetic;
    q.momentum = q.rho * wall_velocity;
    u.set(a, q);
  }

  for (std::size_t s = 0; s < wall_nodes_.size(); ++s) {
    const Index a = wall_nodes_[s];
    Conservative q = u.get(a);
    const double p = gas.pressure(q.rho, q.momentum.x(), q.momentum.y(), q.momentum.z(), q.energy);
    Vec3 wall_velocity = Vec3::Zero();
    if (const int c = wall_moving_condition_[s]; c >= 0)
      wall_velocity = conditions_[std::size_t(c)].wall_velocity(a, x[std::size_t(a)], t);
    const Vec3 relative = q.momentum / q.rho - wall_velocity;
    for (int i = 0; i < wall_num_normals_[s]; ++i) {
      const Vec3& n = wall_normals_[s][std::size_t(i)];
      q.momentum -= q.rho * relative.dot(n) * n;
    }
    q.energy = p / gm1 + 0.5 * q.momentum.squaredNorm() / q.rho;
    u.set(a, q);
  }
}

}  // namespace shellflow::fluid
