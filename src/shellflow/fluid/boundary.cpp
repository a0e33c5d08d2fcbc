#include "shellflow/fluid/boundary.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include "shellflow/core/error.h"
#include "shellflow/core/parallel.h"

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
    case BoundaryKind::supersonic_inflow:
      return 5;
    case BoundaryKind::no_slip_wall:
      return 4;
    case BoundaryKind::slip_wall:
    case BoundaryKind::symmetry:
      return 3;
    case BoundaryKind::far_field:
      return 2;
    case BoundaryKind::supersonic_outflow:
      return 1;
  }
  return 0;
}

bool is_wall(BoundaryKind k) { return k == BoundaryKind::slip_wall || k == BoundaryKind::symmetry; }

/// Boundary passes are cheap per node: worth two threads from a few thousand nodes.
constexpr std::size_t boundary_parallel_threshold = 2048;

/// CSR of faces per node for the nodes in `nodes` (sorted), faces selected by `take`.
template <class Take>
void faces_per_node(const std::vector<Index>& nodes, std::span<const Index> slot_of_node, std::size_t num_faces,
                    const std::function<FaceKey(std::size_t)>& nodes_of, Take&& take, std::vector<Index>& offsets,
                    std::vector<Index>& out) {
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
    case BoundaryKind::supersonic_inflow:
      return "supersonic_inflow";
    case BoundaryKind::supersonic_outflow:
      return "supersonic_outflow";
    case BoundaryKind::slip_wall:
      return "slip_wall";
    case BoundaryKind::symmetry:
      return "symmetry";
    case BoundaryKind::far_field:
      return "far_field";
    case BoundaryKind::no_slip_wall:
      return "no_slip_wall";
  }
  return "?";
}

BoundarySet::BoundarySet(const mesh::Mesh& mesh, std::span<const Index> tets, const IdealGas& gas,
                         std::vector<BoundaryCondition> conditions)
    : conditions_(std::move(conditions)) {
  const Index nn = mesh.num_nodes();
  std::map<std::string, int> by_group;
  for (std::size_t c = 0; c < conditions_.size(); ++c) {
    const auto& bc = conditions_[c];
    const auto& group = mesh.group(bc.group);  // throws InputError naming the groups
    if (group.dim != 2 || group.elements.type != mesh::ElementType::tri3)
      throw InputError(
          fmt::format("fluid boundary condition '{}' on group '{}' of mesh '{}': the group is not a "
                      "surface of 3-node triangles; give conditions on boundary surfaces only",
                      to_string(bc.kind), bc.group, mesh.name));
    if (!by_group.emplace(bc.group, int(c)).second)
      throw InputError(
          fmt::format("fluid boundary group '{}' of mesh '{}' has two conditions; "
                      "keep one",
                      bc.group, mesh.name));
    if (bc.kind == BoundaryKind::supersonic_inflow) {
      // A varying state is checked at the group's first node at t = 0.
      const Primitive s = bc.state_at && !group.nodes.empty()
                              ? bc.state_at(mesh.nodes[std::size_t(group.nodes.front())], 0.0)
                              : bc.state;
      const double c0 = gas.sound_speed(s.rho, s.pressure);
      const double mach = s.velocity.norm() / c0;
      if (!(s.rho > 0.0 && s.pressure > 0.0) || !(mach >= 1.0))
        throw InputError(
            fmt::format("fluid boundary '{}': supersonic_inflow needs a supersonic state with rho, p > 0, "
                        "got rho = {}, p = {}, Mach {:.4g}; use far_field for a subsonic inflow",
                        bc.group, s.rho, s.pressure, mach));
    }
    if (bc.kind == BoundaryKind::no_slip_wall && !gas.viscous())
      throw InputError(
          fmt::format("fluid boundary '{}' of mesh '{}': no_slip_wall needs the viscous terms, but the gas "
                      "is inviscid; set the fluid viscosity (fluid.gas.viscosity: constant or sutherland) "
                      "or use slip_wall",
                      bc.group, mesh.name));
    if (bc.wall_temperature && (bc.kind != BoundaryKind::no_slip_wall || !(*bc.wall_temperature > 0.0) ||
                                !std::isfinite(*bc.wall_temperature)))
      throw InputError(
          fmt::format("fluid boundary '{}' ({}): wall temperature {} K; give a positive temperature on a "
                      "no_slip_wall, or none (adiabatic wall)",
                      bc.group, to_string(bc.kind), *bc.wall_temperature));
  }
  for (const auto& g : mesh.groups)
    if (g.dim == 2 && !by_group.contains(g.name))
      throw InputError(
          fmt::format("fluid boundary group '{}' of mesh '{}' has no boundary condition; give it one of "
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
      const auto it = face_index.find(sorted_key(n[tet_faces[opp][0]], n[tet_faces[opp][1]], n[tet_faces[opp][2]]));
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
          conditions_[std::size_t(f.condition)].group, mesh.name, f.face.nodes[0], f.face.nodes[1], f.face.nodes[2]));
    const auto kind = conditions_[std::size_t(f.condition)].kind;
    if (kind == BoundaryKind::supersonic_outflow || kind == BoundaryKind::far_field) natural_faces_.push_back(f.face);
    if (kind == BoundaryKind::slip_wall) slip_wall_faces_.push_back(f.face);
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
  // Far-field condition of each node (the first far-field group touching it), for the
  // slab rule: a wall/symmetry node on a far-field face gets the far-field state first.
  std::vector<int> far_of_node(static_cast<std::size_t>(nn), -1);
  for (const auto& f : faces_)
    if (conditions_[std::size_t(f.condition)].kind == BoundaryKind::far_field)
      for (const Index a : f.face.nodes)
        if (far_of_node[std::size_t(a)] < 0) far_of_node[std::size_t(a)] = f.condition;
  wall_slot_.assign(std::size_t(nn), -1);
  std::vector<Index> far_slot(static_cast<std::size_t>(nn), -1);
  std::vector<Index> no_slip_slot(static_cast<std::size_t>(nn), -1);
  for (Index a = 0; a < nn; ++a) {
    const int c = node_condition[std::size_t(a)];
    if (c < 0) continue;
    const auto kind = conditions_[std::size_t(c)].kind;
    if (kind == BoundaryKind::supersonic_inflow) {
      inflow_nodes_.emplace_back(a, c);
    } else if (kind == BoundaryKind::no_slip_wall) {
      no_slip_slot[std::size_t(a)] = Index(no_slip_nodes_.size());
      no_slip_nodes_.push_back(a);
      no_slip_condition_.push_back(c);
    } else if (is_wall(kind)) {
      wall_slot_[std::size_t(a)] = Index(wall_nodes_.size());
      wall_nodes_.push_back(a);
    }
    const int far = kind == BoundaryKind::far_field ? c : is_wall(kind) ? far_of_node[std::size_t(a)] : -1;
    if (far >= 0) {
      far_slot[std::size_t(a)] = Index(far_nodes_.size());
      far_nodes_.push_back(a);
      far_condition_.push_back(far);
    }
  }
  // Positions of the nodes in their groups' node lists (per-node wall velocities).
  set_velocity_.assign(conditions_.size(), {});
  group_size_.assign(conditions_.size(), 0);
  no_slip_index_.assign(no_slip_nodes_.size(), -1);
  std::vector<std::vector<GroupSlot>> slip_groups(wall_nodes_.size());
  for (std::size_t c = 0; c < conditions_.size(); ++c) {
    const auto& nodes = mesh.group(conditions_[c].group).nodes;
    group_size_[c] = Index(nodes.size());
    const auto kind = conditions_[c].kind;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const auto a = std::size_t(nodes[i]);
      if (kind == BoundaryKind::slip_wall && wall_slot_[a] >= 0)
        slip_groups[std::size_t(wall_slot_[a])].push_back({int(c), Index(i)});
      if (kind == BoundaryKind::no_slip_wall && no_slip_slot[a] >= 0 &&
          no_slip_condition_[std::size_t(no_slip_slot[a])] == int(c))
        no_slip_index_[std::size_t(no_slip_slot[a])] = Index(i);
    }
  }
  wall_slip_offsets_.assign(1, 0);
  for (const auto& l : slip_groups) {
    wall_slip_groups_.insert(wall_slip_groups_.end(), l.begin(), l.end());
    wall_slip_offsets_.push_back(Index(wall_slip_groups_.size()));
  }
  const std::function<FaceKey(std::size_t)> nodes_of = [&](std::size_t f) { return FaceKey{faces_[f].face.nodes}; };
  // Wall faces: symmetry faces first so that their exact plane normal leads Gram–Schmidt.
  std::vector<Index> sym_offsets, sym_faces, slip_offsets, slip_faces;
  faces_per_node(
      wall_nodes_, wall_slot_, faces_.size(), nodes_of,
      [&](std::size_t f) { return conditions_[std::size_t(faces_[f].condition)].kind == BoundaryKind::symmetry; },
      sym_offsets, sym_faces);
  faces_per_node(
      wall_nodes_, wall_slot_, faces_.size(), nodes_of,
      [&](std::size_t f) { return conditions_[std::size_t(faces_[f].condition)].kind == BoundaryKind::slip_wall; },
      slip_offsets, slip_faces);
  wall_face_offsets_.assign(1, 0);
  wall_sym_faces_.assign(wall_nodes_.size(), 0);
  for (std::size_t s = 0; s < wall_nodes_.size(); ++s) {
    for (Index k = sym_offsets[s]; k < sym_offsets[s + 1]; ++k) wall_faces_.push_back(sym_faces[std::size_t(k)]);
    wall_sym_faces_[s] = sym_offsets[s + 1] - sym_offsets[s];
    for (Index k = slip_offsets[s]; k < slip_offsets[s + 1]; ++k) wall_faces_.push_back(slip_faces[std::size_t(k)]);
    wall_face_offsets_.push_back(Index(wall_faces_.size()));
  }
  faces_per_node(
      far_nodes_, far_slot, faces_.size(), nodes_of,
      [&](std::size_t f) { return conditions_[std::size_t(faces_[f].condition)].kind == BoundaryKind::far_field; },
      far_face_offsets_, far_faces_);
  wall_normals_.resize(wall_nodes_.size());
  wall_num_normals_.assign(wall_nodes_.size(), 0);
  wall_num_sym_normals_.assign(wall_nodes_.size(), 0);
  far_normals_.assign(far_nodes_.size(), Vec3::Zero());
}

void BoundarySet::set_reference_facets(std::span<const Vec3> x) {
  constexpr std::size_t max_facets = 62, max_facets_per_group = 8;
  facets_.clear();
  Vec3 lo = x.empty() ? Vec3::Zero() : x[0], hi = lo;
  for (const Vec3& p : x) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double tolerance = 1e-12 * (hi - lo).norm();
  std::vector<int> facet_of(faces_.size(), -1);
  for (std::size_t c = 0; c < conditions_.size(); ++c) {
    const std::size_t first = facets_.size();
    for (std::size_t f = 0; f < faces_.size(); ++f) {
      if (faces_[f].condition != int(c)) continue;
      const auto& nodes = faces_[f].face.nodes;
      const Vec3 n = face_area_vector(x, faces_[f].face).normalized();
      if (!n.allFinite()) continue;
      const double offset = n.dot(x[std::size_t(nodes[0])]);
      int found = -1;
      for (std::size_t k = first; k < facets_.size() && found < 0; ++k) {
        const Facet& facet = facets_[k];
        bool on = facet.normal.dot(n) > 0.5;
        for (const Index a : nodes)
          on = on && std::abs(facet.normal.dot(x[std::size_t(a)]) - facet.offset) <= facet.tolerance;
        if (on) found = int(k);
      }
      if (found < 0 && facets_.size() < max_facets && facets_.size() - first < max_facets_per_group) {
        found = int(facets_.size());
        facets_.push_back({n, offset, tolerance, {}});
      }
      if (found < 0) continue;
      facet_of[f] = found;
      auto& facet_nodes = facets_[std::size_t(found)].nodes;
      facet_nodes.insert(facet_nodes.end(), nodes.begin(), nodes.end());
    }
  }
  for (Facet& facet : facets_) {
    std::sort(facet.nodes.begin(), facet.nodes.end());
    facet.nodes.erase(std::unique(facet.nodes.begin(), facet.nodes.end()), facet.nodes.end());
  }
  const auto bits_of = [&](std::span<const Index> offsets, std::span<const Index> faces,
                           std::vector<std::uint64_t>& out) {
    out.assign(offsets.size() - 1, 0);
    for (std::size_t s = 0; s + 1 < offsets.size(); ++s)
      for (Index k = offsets[s]; k < offsets[s + 1]; ++k) {
        const int facet = facet_of[std::size_t(faces[std::size_t(k)])];
        out[s] |= std::uint64_t{1} << (facet < 0 ? 63 : facet);
      }
  };
  bits_of(wall_face_offsets_, wall_faces_, wall_facets_);
  bits_of(far_face_offsets_, far_faces_, far_facets_);
  have_reference_ = true;
}

std::uint64_t BoundarySet::facets_off_their_planes(std::span<const Vec3> x) const {
  std::uint64_t off = std::uint64_t{1} << 63;
  for (std::size_t k = 0; k < facets_.size(); ++k) {
    const Facet& facet = facets_[k];
    const auto n = std::ptrdiff_t(facet.nodes.size());
    const bool on = parallel::reduce(
        Index(n),
        parallel::grain_if(std::size_t(n) > 8 * boundary_parallel_threshold, Index(8 * boundary_parallel_threshold),
                           Index(n)),
        true,
        [&](Index begin, Index end) {
          bool in_plane = true;
          for (Index i = begin; i < end && in_plane; ++i)
            in_plane = std::abs(facet.normal.dot(x[std::size_t(facet.nodes[std::size_t(i)])]) - facet.offset) <=
                       facet.tolerance;
          return in_plane;
        },
        [](bool p, bool q) { return p && q; });
    if (!on) off |= std::uint64_t{1} << k;
  }
  return off;
}

void BoundarySet::update_wall_node(std::size_t s, std::span<const Vec3> x) {
  const double cos30 = std::sqrt(3.0) / 2.0;
  // Cluster the adjacent face normals; each cluster is one wall direction. Symmetry
  // faces come first, so the clusters they open come first.
  std::array<Vec3, 8> clusters;
  int nc = 0, nc_sym = 0;
  for (Index k = wall_face_offsets_[s]; k < wall_face_offsets_[s + 1]; ++k) {
    const Vec3 a = face_area_vector(x, faces_[std::size_t(wall_faces_[std::size_t(k)])].face);
    const Vec3 n = a.normalized();
    int found = -1;
    for (int c = 0; c < nc && found < 0; ++c)
      if (clusters[std::size_t(c)].normalized().dot(n) > cos30) found = c;
    if (found >= 0) {
      clusters[std::size_t(found)] += a;
    } else if (nc < int(clusters.size())) {
      clusters[std::size_t(nc++)] = a;
      if (k - wall_face_offsets_[s] < wall_sym_faces_[s]) nc_sym = nc;
    }
  }
  // Gram–Schmidt: the constrained subspace spanned by the distinct normals.
  int m = 0, m_sym = 0;
  auto& basis = wall_normals_[s];
  for (int c = 0; c < nc && m < 3; ++c) {
    Vec3 v = clusters[std::size_t(c)].normalized();
    for (int i = 0; i < m; ++i) v -= v.dot(basis[std::size_t(i)]) * basis[std::size_t(i)];
    const double len = v.norm();
    if (len > 1e-6) {
      basis[std::size_t(m++)] = v / len;
      if (c < nc_sym) m_sym = m;
    }
  }
  wall_num_normals_[s] = m;
  wall_num_sym_normals_[s] = m_sym;
}

void BoundarySet::update_far_node(std::size_t s, std::span<const Vec3> x) {
  Vec3 n = Vec3::Zero();
  for (Index k = far_face_offsets_[s]; k < far_face_offsets_[s + 1]; ++k)
    n += face_area_vector(x, faces_[std::size_t(far_faces_[std::size_t(k)])].face);
  far_normals_[s] = n.normalized();
}

void BoundarySet::restore_reference_node(std::size_t s, bool wall) {
  if (wall) {
    wall_normals_[s] = reference_wall_normals_[s];
    wall_num_normals_[s] = reference_wall_num_normals_[s];
    wall_num_sym_normals_[s] = reference_wall_num_sym_normals_[s];
  } else {
    far_normals_[s] = reference_far_normals_[s];
  }
}

void BoundarySet::update_normals(std::span<const Vec3> x) {
  // Normals at the reference are computed for every node; afterwards only for the nodes
  // with a face in no facet or in a facet off its reference plane, and a node whose facets
  // came back into their planes gets its reference normals back: the result depends on x
  // only, not on the configurations before. A face's area vector is formed by each node
  // that needs it (no shared work array, no face pass).
  const bool all = !have_reference_;
  if (all) set_reference_facets(x);
  const std::uint64_t off = all ? ~std::uint64_t{0} : facets_off_their_planes(x);
  const std::uint64_t back = all ? 0 : last_off_ & ~off;
  const auto nw = Index(wall_nodes_.size());
  Index updated = parallel::reduce(
      nw, parallel::grain_if(std::size_t(nw) > boundary_parallel_threshold, Index(boundary_parallel_threshold), nw),
      Index{0},
      [&](Index begin, Index end) {
        Index count = 0;
        for (Index si = begin; si < end; ++si) {
          const std::uint64_t facets = wall_facets_[std::size_t(si)];
          if (facets & off) {
            update_wall_node(std::size_t(si), x);
            ++count;
          } else if (facets & back) {
            restore_reference_node(std::size_t(si), true);
          }
        }
        return count;
      },
      [](Index p, Index q) { return p + q; });
  for (std::size_t s = 0; s < far_nodes_.size(); ++s) {
    if (far_facets_[s] & off) {
      update_far_node(s, x);
      ++updated;
    } else if (far_facets_[s] & back) {
      restore_reference_node(s, false);
    }
  }
  if (all) {
    reference_wall_normals_ = wall_normals_;
    reference_wall_num_normals_ = wall_num_normals_;
    reference_wall_num_sym_normals_ = wall_num_sym_normals_;
    reference_far_normals_ = far_normals_;
  }
  last_off_ = all ? 0 : off;
  normals_updated_ = updated;
}

BoundaryFace BoundarySet::owner_of(Index a, Index b, Index c) const {
  const auto it = face_index_.find(sorted_key(a, b, c));
  if (it == face_index_.end())
    throw InputError(
        fmt::format("triangle ({} {} {}) is not a face of a fluid boundary group "
                    "with a condition",
                    a, b, c));
  return faces_[it->second].face;
}

std::span<const Vec3> BoundarySet::wall_constraints(Index node) const {
  const Index s = wall_slot_.empty() ? -1 : wall_slot_[std::size_t(node)];
  if (s < 0) return {};
  return {wall_normals_[std::size_t(s)].data(), std::size_t(wall_num_normals_[std::size_t(s)])};
}

int BoundarySet::symmetry_constraints(Index node) const {
  const Index s = wall_slot_.empty() ? -1 : wall_slot_[std::size_t(node)];
  return s < 0 ? 0 : wall_num_sym_normals_[std::size_t(s)];
}

}  // namespace shellflow::fluid
