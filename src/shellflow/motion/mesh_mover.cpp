#include "shellflow/motion/mesh_mover.h"

#include <cmath>

#include "shellflow/core/error.h"
#include "shellflow/core/parallel.h"

namespace shellflow::motion {
namespace {

std::vector<Vec3> gather(std::span<const Vec3> x, std::span<const Index> nodes) {
  std::vector<Vec3> out(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) out[i] = x[static_cast<std::size_t>(nodes[i])];
  return out;
}

std::vector<double> lumped_group_areas(const mesh::Mesh& m, const std::vector<std::string>& groups) {
  std::vector<double> area(m.nodes.size(), 0.0);
  for (const auto& name : groups) {
    const auto a = lumped_node_areas(m.nodes, m.group(name).elements);
    for (std::size_t i = 0; i < a.size(); ++i) area[i] += a[i];
  }
  return area;
}

}  // namespace

FluidBoundaryNodes classify_fluid_boundary(const mesh::Mesh& fluid, const BoundaryGroups& groups) {
  const auto c = classify_nodes(fluid, groups.interface_groups, groups.fixed_groups, groups.sliding_groups);
  const auto interface_area = lumped_group_areas(fluid, groups.interface_groups);
  const auto fixed_area = lumped_group_areas(fluid, groups.fixed_groups);
  FluidBoundaryNodes b;
  for (Index i = 0; i < fluid.num_nodes(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    switch (c.classes[k]) {
      case NodeClass::interface:
        b.interface_nodes.push_back(i);
        b.interface_areas.push_back(interface_area[k]);
        break;
      case NodeClass::fixed:
        b.fixed_nodes.push_back(i);
        b.fixed_areas.push_back(fixed_area[k]);
        break;
      case NodeClass::sliding:
        b.sliding_nodes.push_back(i);
        b.sliding_normals.push_back(c.sliding_normals[k]);
        break;
      case NodeClass::interior:
        break;
    }
  }
  return b;
}

// ---------------------------------------------------------------- SpaceMeshMover

SpaceMeshMover::SpaceMeshMover(const mesh::Mesh& fluid, const mesh::Mesh& space, SpaceMeshOptions options,
                               BoundaryMotion& motion, std::vector<Vec3> samples, std::vector<double> sample_areas)
    : space_(space, options), motion_(motion), fluid_initial_(fluid.nodes) {
  const BoundaryGroups groups{options.interface_groups, options.fixed_groups, options.sliding_groups};
  const auto fluid_boundary = classify_fluid_boundary(fluid, groups);
  fluid_interface_ = fluid_boundary.interface_nodes;
  if (samples.empty()) {
    samples = gather(fluid.nodes, fluid_interface_);
    sample_areas = fluid_boundary.interface_areas;
  }
  space_.set_interface_samples(samples, sample_areas);
  report_ = space_.locate(fluid.nodes);

  space_handle_ = motion_.register_points(gather(space.nodes, space_.interface_nodes()));
  sample_handle_ = motion_.register_points(samples);
  fluid_handle_ = motion_.register_points(gather(fluid.nodes, fluid_interface_));
  iu_.resize(space_.interface_nodes().size());
  iv_.resize(iu_.size());
  su_.resize(samples.size());
  sv_.resize(samples.size());
  fu_.resize(fluid_interface_.size());
  fv_.resize(fluid_interface_.size());
}

void SpaceMeshMover::move_time_modes() {
  // The space mesh, its interpolation and the exact wall placement are linear in the
  // boundary motion: each time mode is moved once per window.
  const int k_modes = motion_.num_time_modes();
  modes_.modes = k_modes;
  modes_.space.resize(std::size_t(k_modes));
  modes_.fluid.resize(std::size_t(k_modes));
  std::fill(iv_.begin(), iv_.end(), Vec3::Zero());
  std::fill(sv_.begin(), sv_.end(), Vec3::Zero());
  for (int k = 0; k < k_modes; ++k) {
    motion_.evaluate_time_mode(space_handle_, k, iu_);
    motion_.evaluate_time_mode(sample_handle_, k, su_);
    space_.move(iu_, iv_, su_, sv_);
    const auto u = space_.displacement();
    modes_.space[std::size_t(k)].assign(u.begin(), u.end());
    auto& fluid = modes_.fluid[std::size_t(k)];
    fluid.resize(fluid_initial_.size());
    space_.interpolate_displacement(fluid);
    motion_.evaluate_time_mode(fluid_handle_, k, fu_);
    for (std::size_t i = 0; i < fluid_interface_.size(); ++i) fluid[std::size_t(fluid_interface_[i])] = fu_[i];
  }
  modes_.window = motion_.window_id();
}

void SpaceMeshMover::update(double time, std::span<Vec3> x, std::span<Vec3> w) {
  if (motion_.num_time_modes() > 0 && motion_.num_time_modes() <= BoundaryMotion::max_time_modes) {
    if (modes_.modes != motion_.num_time_modes() || modes_.window != motion_.window_id()) move_time_modes();
    const auto k_modes = std::size_t(modes_.modes);
    std::array<double, BoundaryMotion::max_time_modes> c{}, dc{};
    motion_.time_coefficients(time, std::span(c).first(k_modes), std::span(dc).first(k_modes));
    // The space mesh's own nodes (its frames and the Jacobian check).
    const std::size_t ns = modes_.space[0].size();
    space_u_.assign(ns, Vec3::Zero());
    space_v_.assign(ns, Vec3::Zero());
    for (std::size_t k = 0; k < k_modes; ++k)
      for (std::size_t i = 0; i < ns; ++i) {
        space_u_[i] += c[k] * modes_.space[k][i];
        space_v_[i] += dc[k] * modes_.space[k][i];
      }
    space_.set_node_motion(space_u_, space_v_);
    const bool velocities = !w.empty();
    const auto n = std::ptrdiff_t(fluid_initial_.size());
    parallel::for_range(Index(n), parallel::grain_if(n > 4096, 1024, Index(n)),
                        [&](Index begin, Index end) {  // ~100 k multiply-adds
                          for (Index p = begin; p < end; ++p) {
                            const auto i = std::size_t(p);
                            Vec3 u = Vec3::Zero(), v = Vec3::Zero();
                            for (std::size_t k = 0; k < k_modes; ++k) {
                              u += c[k] * modes_.fluid[k][i];
                              if (velocities) v += dc[k] * modes_.fluid[k][i];
                            }
                            x[i] = fluid_initial_[i] + u;
                            if (velocities) w[i] = v;
                          }
                        });
    return;
  }
  motion_.evaluate(space_handle_, time, iu_, iv_);
  motion_.evaluate(sample_handle_, time, su_, sv_);
  space_.move(iu_, iv_, su_, sv_);
  space_.interpolate(x, w);
  // The fluid wall follows the boundary motion exactly, not its cubic approximation.
  motion_.evaluate(fluid_handle_, time, fu_, fv_);
  for (std::size_t i = 0; i < fluid_interface_.size(); ++i) {
    const auto node = static_cast<std::size_t>(fluid_interface_[i]);
    x[node] = fluid_initial_[node] + fu_[i];
    if (!w.empty()) w[node] = fv_[i];
  }
}

std::size_t SpaceMeshMover::memory_bytes() const {
  // Locations (element + 20 shape values per fluid node) and the IDW weight rows.
  const std::size_t idw_rows =
      space_.mesh().nodes.size() - space_.interface_nodes().size() - space_.fixed_nodes().size();
  std::size_t mode_bytes = 0;
  for (std::size_t k = 0; k < modes_.space.size(); ++k)
    mode_bytes += (modes_.space[k].size() + modes_.fluid[k].size()) * sizeof(Vec3);
  return space_.locations().size() * sizeof(NodeLocation) +
         idw_rows * (su_.size() + space_.fixed_nodes().size()) * sizeof(double) + mode_bytes;
}

// ---------------------------------------------------------------- DirectIdwMover

DirectIdwMover::DirectIdwMover(const mesh::Mesh& fluid, const BoundaryGroups& groups, BoundaryMotion& motion,
                               double interface_exponent, double fixed_exponent, IdwWeighting weighting)
    : fluid_(fluid),
      boundary_(classify_fluid_boundary(fluid, groups)),
      motion_(motion),
      e1_(interface_exponent),
      e2_(fixed_exponent),
      weighting_(weighting) {
  std::vector<bool> on_boundary(fluid.nodes.size(), false);
  for (Index i : boundary_.interface_nodes) on_boundary[static_cast<std::size_t>(i)] = true;
  for (Index i : boundary_.fixed_nodes) on_boundary[static_cast<std::size_t>(i)] = true;
  std::vector<std::array<Vec3, 2>> normals(fluid.nodes.size(), {Vec3::Zero(), Vec3::Zero()});
  for (std::size_t s = 0; s < boundary_.sliding_nodes.size(); ++s)
    normals[static_cast<std::size_t>(boundary_.sliding_nodes[s])] = boundary_.sliding_normals[s];
  for (Index i = 0; i < fluid.num_nodes(); ++i) {
    if (on_boundary[static_cast<std::size_t>(i)]) continue;
    free_nodes_.push_back(i);
    free_normals_.push_back(normals[static_cast<std::size_t>(i)]);
  }
  handle_ = motion_.register_points(gather(fluid.nodes, boundary_.interface_nodes));
  iu_.resize(boundary_.interface_nodes.size());
  iv_.resize(iu_.size());
}

void DirectIdwMover::update(double time, std::span<Vec3> x, std::span<Vec3> w) {
  motion_.evaluate(handle_, time, iu_, iv_);
  const auto& X = fluid_.nodes;
  const bool by_area = weighting_ == IdwWeighting::area;
  for (std::size_t i = 0; i < boundary_.interface_nodes.size(); ++i) {
    const auto node = static_cast<std::size_t>(boundary_.interface_nodes[i]);
    x[node] = X[node] + iu_[i];
    if (!w.empty()) w[node] = iv_[i];
  }
  for (Index node : boundary_.fixed_nodes) {
    x[static_cast<std::size_t>(node)] = X[static_cast<std::size_t>(node)];
    if (!w.empty()) w[static_cast<std::size_t>(node)] = Vec3::Zero();
  }
  const auto n = static_cast<std::ptrdiff_t>(free_nodes_.size());
  parallel::for_range(Index(n), 64, [&](Index begin, Index end) {
    for (Index f = begin; f < end; ++f) {
      const auto node = static_cast<std::size_t>(free_nodes_[static_cast<std::size_t>(f)]);
      const Vec3& p = X[node];
      Vec3 u = Vec3::Zero(), v = Vec3::Zero();
      double sum = 0.0;
      for (std::size_t j = 0; j < boundary_.interface_nodes.size(); ++j) {
        const double d = (p - X[static_cast<std::size_t>(boundary_.interface_nodes[j])]).norm();
        const double a = (by_area ? boundary_.interface_areas[j] : 1.0) / std::pow(d, e1_);
        u += a * iu_[j];
        v += a * iv_[j];
        sum += a;
      }
      for (std::size_t l = 0; l < boundary_.fixed_nodes.size(); ++l) {
        const double d = (p - X[static_cast<std::size_t>(boundary_.fixed_nodes[l])]).norm();
        sum += (by_area ? boundary_.fixed_areas[l] : 1.0) / std::pow(d, e2_);
      }
      const auto& normals = free_normals_[static_cast<std::size_t>(f)];
      x[node] = p + project_on_sliding_planes(u / sum, normals);
      if (!w.empty()) w[node] = project_on_sliding_planes(v / sum, normals);
    }
  });
}

std::size_t DirectIdwMover::memory_bytes() const {
  return (free_nodes_.size() + boundary_.interface_nodes.size() + boundary_.fixed_nodes.size()) * sizeof(Index);
}

}  // namespace shellflow::motion
