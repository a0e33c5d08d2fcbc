#include "shellflow/setup/shell_setup.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <string>

#include "shellflow/core/error.h"
#include "shellflow/mesh/spatial_index.h"

namespace shellflow::setup {
namespace {

/// A symmetry support holds each node in the plane through it with normal n, so every edge
/// of its group must lie in such a plane (two parallel edges, as the strip's two sides, are
/// fine): refuses an edge element whose nodes spread along n (a mistyped normal would
/// otherwise pin the edge's in-plane motion without a word).
void check_symmetry_plane(const mesh::Mesh& mesh, const std::string& group, const Vec3& normal) {
  const Vec3 n = normal.normalized();
  const mesh::ElementBlock& edges = mesh.group(group).elements;
  for (Index e = 0; e < edges.size(); ++e) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    Eigen::AlignedBox<double, 3> box;
    for (const Index k : edges.element(e)) {
      const Vec3& x = mesh.nodes[static_cast<std::size_t>(k)];
      lo = std::min(lo, x.dot(n));
      hi = std::max(hi, x.dot(n));
      box.extend(x);
    }
    if (hi - lo > 1e-6 * box.diagonal().norm())
      throw InputError(fmt::format(
          "symmetry support on '{}': its edge near ({:.6g}, {:.6g}, {:.6g}) does not lie in a plane with normal "
          "({:.6g}, {:.6g}, {:.6g}) (its nodes spread over {:.6g} m along it); give the normal of the symmetry "
          "plane that contains the edge",
          group, box.center().x(), box.center().y(), box.center().z(), n.x(), n.y(), n.z(), hi - lo));
  }
}

}  // namespace

shell::ShellModel build_shell_model(const io::ShellSection& s, const mesh::Mesh& mesh) {
  shell::ShellSection section;
  section.thickness = s.thickness;
  section.material = {s.material.young_modulus, s.material.poisson_ratio, s.material.density};
  shell::ShellModel model(mesh, section);
  for (const io::Support& support : s.supports) {
    // The model's messages name the mesh and group; the case file's line goes in front.
    try {
      switch (support.type) {
        case io::SupportType::clamped:
          model.add_support(shell::Support::clamped(support.group));
          break;
        case io::SupportType::simply_supported:
          model.add_support(shell::Support::simply_supported(support.group));
          break;
        case io::SupportType::simply_supported_hard:
          model.add_hard_simple_support(support.group);
          break;
        case io::SupportType::symmetry:
          check_symmetry_plane(mesh, support.group, support.normal);
          model.add_support(shell::DirectionalSupport::symmetry_plane(support.group, support.normal));
          break;
        case io::SupportType::sliding:
          model.add_support(
              shell::DirectionalSupport::roller(support.group, support.direction, support.clamp_director));
          break;
        case io::SupportType::prescribed: {
          shell::PrescribedMotion motion;
          motion.group = support.group;
          motion.displacement = support.displacement;
          // Without its own history the motion scales like the loads: with the load factor
          // (the pseudo-time of a static run) or the dynamic load function.
          const bool dynamic = s.analysis && s.analysis->type == io::ShellAnalysisType::dynamic;
          motion.displacement_history = support.displacement_history ? *support.displacement_history
                                        : dynamic                    ? s.analysis->load_function
                                                                     : TimeFunction::ramp(1.0, 1.0);
          motion.rotation_axis = support.rotation_axis;
          motion.rotation_angle = support.rotation_angle;
          model.add_prescribed_motion(motion);
          break;
        }
      }
    } catch (const InputError& e) {
      throw_at(support.where, e.what());
    }
  }
  const mesh::PointIndex nodes(mesh.nodes);
  for (const io::ShellLoad& load : s.loads) {
    switch (load.type) {
      case io::ShellLoadType::line:
        model.add_line_load({load.group, load.vector});
        break;
      case io::ShellLoadType::point: {
        const auto hit = nodes.nearest(load.point);
        if (hit.distance > 1e-6 * model.reference_length()) {
          throw_at(load.where, fmt::format("no shell node at ({}, {}, {}): the nearest is {:.3g} m "
                                           "away; put point loads on a node",
                                           load.point.x(), load.point.y(), load.point.z(), hit.distance));
        }
        model.add_point_load({hit.index, load.vector});
        break;
      }
      case io::ShellLoadType::edge_couple:
        model.add_edge_couple({load.group, load.vector, load.value});
        break;
      case io::ShellLoadType::pressure:
        model.add_follower_pressure({load.group, load.value});
        break;
      case io::ShellLoadType::gravity:
        model.add_gravity(load.vector);
        break;
      case io::ShellLoadType::surface:
        model.add_surface_traction({load.group, load.vector});
        break;
    }
  }
  return model;
}

shell::NewmarkOptions newmark_options(const io::ShellAnalysis& analysis) {
  shell::NewmarkOptions options;
  options.mass_damping = analysis.mass_damping;
  options.newton.modified = analysis.modified_newton;
  options.scheme =
      analysis.scheme == io::TimeScheme::midpoint ? shell::TimeScheme::midpoint : shell::TimeScheme::newmark;
  return options;
}

}  // namespace shellflow::setup
