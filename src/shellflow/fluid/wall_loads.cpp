// The loads of the gas on a boundary group (paper eq. 30, fluid.md §12): pressure force,
// full viscous force, nodal traction, and the wall shear a coupled run transfers to the shell.
#include <fmt/format.h>

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

#include "shellflow/core/error.h"
#include "shellflow/fluid/fluid_model.h"
#include "shellflow/fluid/viscous.h"

namespace shellflow::fluid {

Vec3 FluidModel::pressure_force(std::string_view group_name) const {
  const auto& group = mesh_.group(group_name);
  // Each face is oriented away from the fourth node of the tetrahedron that owns it.
  Vec3 force = Vec3::Zero();
  for (Index f = 0; f < group.elements.size(); ++f) {
    const auto n = group.elements.element(f);
    const BoundaryFace face = boundaries_.owner_of(n[0], n[1], n[2]);
    const Vec3 area = face_area_vector(x_, face);
    double p = 0.0;
    for (const Index a : n)
      p += options_.gas.pressure(state_.var[0][std::size_t(a)], state_.var[1][std::size_t(a)],
                                 state_.var[2][std::size_t(a)], state_.var[3][std::size_t(a)],
                                 state_.var[4][std::size_t(a)]);
    force += area * (p / 3.0);
  }
  return force;
}

Vec3 FluidModel::viscous_force(std::string_view group_name) const {
  const auto& group = mesh_.group(group_name);
  const WallTraction w = wall_traction(group_name);
  std::vector<Index> slot(std::size_t(mesh_.num_nodes()), -1);
  for (std::size_t s = 0; s < w.nodes.size(); ++s) slot[std::size_t(w.nodes[s])] = Index(s);
  // p and tau linear on each face, with the face's own normal (so a uniform state on a
  // closed surface gives exactly zero).
  Vec3 force = Vec3::Zero();
  for (Index f = 0; f < group.elements.size(); ++f) {
    const auto n = group.elements.element(f);
    const Vec3 area = face_area_vector(x_, boundaries_.owner_of(n[0], n[1], n[2]));
    double p = 0.0;
    Mat3 tau = Mat3::Zero();
    for (const Index a : n) {
      const auto s = std::size_t(slot[std::size_t(a)]);
      p += w.pressure[s];
      tau += w.stress[s];
    }
    force += (p / 3.0) * area - (tau / 3.0) * area;
  }
  return force;
}

WallTraction FluidModel::wall_traction(std::string_view group_name) const {
  const auto& group = mesh_.group(group_name);
  WallTraction out;
  out.nodes = group.nodes;
  const std::size_t nn = out.nodes.size();
  std::vector<Index> slot(std::size_t(mesh_.num_nodes()), -1);
  for (std::size_t s = 0; s < nn; ++s) slot[std::size_t(out.nodes[s])] = Index(s);
  out.normal.assign(nn, Vec3::Zero());
  for (Index f = 0; f < group.elements.size(); ++f) {
    const auto n = group.elements.element(f);
    const Vec3 area = face_area_vector(x_, boundaries_.owner_of(n[0], n[1], n[2]));
    for (const Index a : n) out.normal[std::size_t(slot[std::size_t(a)])] += area;
  }
  for (auto& n : out.normal) n.normalize();
  // Nodal stress: volume-weighted mean of the adjacent elements' (constant) stresses.
  std::vector<Mat3> stress(nn, Mat3::Zero());
  if (options_.gas.viscous()) {
    std::vector<double> volume(nn, 0.0);
    for (std::size_t e = 0; e < tets_.size() / 4; ++e) {
      const Index* t = tets_.data() + 4 * e;
      bool touches = false;
      for (int a = 0; a < 4; ++a) touches = touches || slot[std::size_t(t[a])] >= 0;
      if (!touches) continue;
      const Mat3 tau = element_viscous_flux(options_.gas, t, geometry_.grad[e].data(), state_).stress;
      for (int a = 0; a < 4; ++a)
        if (const Index s = slot[std::size_t(t[a])]; s >= 0) {
          stress[std::size_t(s)] += geometry_.volume[e] * tau;
          volume[std::size_t(s)] += geometry_.volume[e];
        }
    }
    for (std::size_t s = 0; s < nn; ++s) stress[s] /= volume[s];
  }
  out.traction.resize(nn);
  out.shear.resize(nn);
  out.pressure.resize(nn);
  for (std::size_t s = 0; s < nn; ++s) {
    const Vec3& n = out.normal[s];
    out.pressure[s] = primitive(out.nodes[s]).pressure;
    out.shear[s] = -(stress[s] * n);
    out.traction[s] = out.pressure[s] * n + out.shear[s];
  }
  out.stress = std::move(stress);
  return out;
}

namespace {

std::array<Index, 3> sorted_key(Index a, Index b, Index c) {
  std::array<Index, 3> k = {a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}

using FaceSet = std::unordered_set<std::array<Index, 3>, FaceKeyHash>;

/// Adds the faces of the mesh group `group` (sorted node triples) to `out`.
void add_faces(const mesh::Mesh& mesh, std::string_view group, FaceSet& out) {
  const auto& g = mesh.group(group);
  for (Index f = 0; f < g.elements.size(); ++f) {
    const auto n = g.elements.element(f);
    out.insert(sorted_key(n[0], n[1], n[2]));
  }
}

/// The faces of the groups of the conditions of kind `kind`.
FaceSet faces_of(const mesh::Mesh& mesh, const std::vector<BoundaryCondition>& conditions, BoundaryKind kind) {
  FaceSet out;
  for (const BoundaryCondition& bc : conditions)
    if (bc.kind == kind) add_faces(mesh, bc.group, out);
  return out;
}

}  // namespace

const FluidModel::WallShearStencil& FluidModel::shear_stencil(std::string_view group_name) {
  for (const WallShearStencil& st : shear_stencils_)
    if (st.group == group_name) return st;
  const auto& group = mesh_.group(group_name);
  const std::span<const Index> nodes = group.nodes;
  const auto slot = [&](Index node) {
    const auto it = std::lower_bound(nodes.begin(), nodes.end(), node);
    return it != nodes.end() && *it == node ? Index(it - nodes.begin()) : Index(-1);
  };
  WallShearStencil st;
  st.group = std::string(group_name);
  st.corner.assign(nodes.size(), 0);
  // The elements around the group's nodes, and the boundary faces among their faces (a face
  // with a node of the group is a face of these elements only).
  std::unordered_map<std::array<Index, 3>, std::pair<int, BoundaryFace>, FaceKeyHash> faces;
  for (std::size_t e = 0; e < tets_.size() / 4; ++e) {
    const Index* t = tets_.data() + 4 * e;
    std::array<Index, 4> s{};
    bool touches = false;
    for (std::size_t a = 0; a < 4; ++a) touches = (s[a] = slot(t[a])) >= 0 || touches;
    if (!touches) continue;
    st.elements.push_back({Index(e), s});
    for (std::size_t k = 0; k < 4; ++k) {  // the face opposite node k
      const Index a = t[(k + 1) % 4], b = t[(k + 2) % 4], c = t[(k + 3) % 4];
      if (slot(a) < 0 && slot(b) < 0 && slot(c) < 0) continue;
      auto& entry = faces[sorted_key(a, b, c)];
      entry.first += 1;
      entry.second = BoundaryFace{{a, b, c}, Index(e), t[k]};
    }
  }
  FaceSet own;
  add_faces(mesh_, st.group, own);
  const auto no_slip = faces_of(mesh_, boundaries_.conditions(), BoundaryKind::no_slip_wall);
  const auto symmetry = faces_of(mesh_, boundaries_.conditions(), BoundaryKind::symmetry);
  // Unit normals of the group's own faces at each node, to tell a coplanar no-slip neighbour
  // (the same wall going on) from a corner.
  std::vector<std::vector<Vec3>> own_normals(nodes.size());
  for (const auto& [key, entry] : faces)
    if (entry.first == 1 && own.count(key)) {
      const Vec3 n = face_area_vector(x_, entry.second).normalized();
      for (const Index a : key)
        if (const Index sa = slot(a); sa >= 0) own_normals[std::size_t(sa)].push_back(n);
    }
  for (const auto& [key, entry] : faces) {
    if (entry.first != 1) continue;  // an interior face
    const std::array<Index, 3> s = {slot(key[0]), slot(key[1]), slot(key[2])};
    const BoundaryFace& face = entry.second;
    if (own.count(key)) {
      st.own_faces.push_back({face, s});
      st.area_faces.push_back({face, s});
    } else if (symmetry.count(key)) {
      st.symmetry_faces.push_back({face, s});
    } else {
      const Vec3 n = face_area_vector(x_, face).normalized();
      for (std::size_t k = 0; k < 3; ++k) {
        if (s[k] < 0) continue;
        bool coplanar = no_slip.count(key) > 0;
        for (const Vec3& m : own_normals[std::size_t(s[k])]) coplanar = coplanar && n.dot(m) > kCoplanarWall;
        if (coplanar)
          st.area_faces.push_back({face, {s[k], -1, -1}});
        else
          st.corner[std::size_t(s[k])] = 1;
      }
    }
  }
  shear_stencils_.push_back(std::move(st));
  return shear_stencils_.back();
}

void FluidModel::wall_shear(std::string_view group_name, std::span<Vec3> out) {
  const std::size_t nn = mesh_.group(group_name).nodes.size();
  if (out.size() != nn)
    throw InputError(
        fmt::format("wall shear of '{}': {} values asked for, the group has {} nodes", group_name, out.size(), nn));
  std::fill(out.begin(), out.end(), Vec3::Zero());
  if (!options_.gas.viscous()) return;
  const WallShearStencil& st = shear_stencil(group_name);
  // The reaction of the viscous residual: F_a = -sum_e V_e tau_e grad N_a, the force of the
  // gas's stress on the wall at node a (the boundary term of the weak form).
  for (const auto& [e, slots] : st.elements) {
    const auto ue = std::size_t(e);
    const double* B = geometry_.grad[ue].data();
    const Mat3 tau = element_viscous_flux(options_.gas, tets_.data() + 4 * ue, B, state_).stress;
    for (std::size_t a = 0; a < 4; ++a)
      if (slots[a] >= 0)
        out[std::size_t(slots[a])] -= geometry_.volume[ue] * (tau * Vec3(B[3 * a], B[3 * a + 1], B[3 * a + 2]));
  }
  // Spread over the node's share of the wall, integral of N_a dA = A_f / 3 per face.
  std::vector<double> area(nn, 0.0);
  for (const auto& [face, slots] : st.area_faces) {
    const double third = face_area_vector(x_, face).norm() / 3.0;
    for (const Index s : slots)
      if (s >= 0) area[std::size_t(s)] += third;
  }
  for (std::size_t s = 0; s < nn; ++s)
    if (area[s] > 0.0) out[s] /= area[s];
  // At a corner (another boundary at an angle: its flux is in the reaction too), the wall
  // elements' one-sided stress, area-weighted over the node's own faces.
  std::fill(area.begin(), area.end(), 0.0);
  for (const auto& [face, slots] : st.own_faces) {
    if (!std::any_of(slots.begin(), slots.end(), [&](Index s) { return s >= 0 && st.corner[std::size_t(s)]; }))
      continue;
    const auto ue = std::size_t(face.element);
    const Mat3 tau =
        element_viscous_flux(options_.gas, tets_.data() + 4 * ue, geometry_.grad[ue].data(), state_).stress;
    const Vec3 a = face_area_vector(x_, face);
    for (const Index s : slots)
      if (s >= 0 && st.corner[std::size_t(s)]) {
        if (area[std::size_t(s)] == 0.0) out[std::size_t(s)] = Vec3::Zero();
        out[std::size_t(s)] -= tau * a;
        area[std::size_t(s)] += a.norm();
      }
  }
  for (std::size_t s = 0; s < nn; ++s)
    if (st.corner[s] && area[s] > 0.0) out[s] /= area[s];
  // A symmetry plane takes the normal reaction; the wall's shear has no component across it.
  for (const auto& [face, slots] : st.symmetry_faces) {
    const Vec3 n = face_area_vector(x_, face).normalized();
    for (const Index s : slots)
      if (s >= 0) out[std::size_t(s)] -= out[std::size_t(s)].dot(n) * n;
  }
}

}  // namespace shellflow::fluid
