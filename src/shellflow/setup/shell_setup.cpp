#include "shellflow/setup/shell_setup.h"

#include <fmt/format.h>

#include "shellflow/core/error.h"
#include "shellflow/mesh/spatial_index.h"

namespace shellflow::setup {

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
