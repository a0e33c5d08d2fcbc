#include "shell_run.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <tuple>
#include <utility>

#include "shellflow/core/error.h"
#include "shellflow/core/progress.h"
#include "shellflow/io/mesh_output.h"
#include "shellflow/io/pvd_writer.h"
#include "shellflow/mesh/spatial_index.h"
#include "shellflow/shell/newmark_solver.h"
#include "shellflow/shell/shell_model.h"
#include "shellflow/shell/shell_stress.h"
#include "shellflow/shell/static_solver.h"

namespace shellflow::app {
namespace {

shell::ShellModel build_model(const io::ShellSection& s, const mesh::Mesh& mesh) {
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
          model.add_support(
              shell::DirectionalSupport::symmetry_plane(support.group, support.normal));
          break;
        case io::SupportType::sliding:
          model.add_support(shell::DirectionalSupport::roller(support.group, support.direction,
                                                              support.clamp_director));
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
          throw_at(load.where,
                   fmt::format("no shell node at ({}, {}, {}): the nearest is {:.3g} m "
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

/// Node-major 3-vectors of the dofs [offset, offset + 3) of every node.
std::vector<double> nodal_part(const Eigen::VectorXd& u, Index nodes, int offset) {
  std::vector<double> out(3 * static_cast<std::size_t>(nodes));
  for (Index n = 0; n < nodes; ++n)
    for (int i = 0; i < 3; ++i)
      out[3 * static_cast<std::size_t>(n) + static_cast<std::size_t>(i)] =
          u[shell::dofs_per_node * n + offset + i];
  return out;
}

/// One nodal field for the VTU: name, components, values (owned).
using OwnedField = std::tuple<std::string, int, std::vector<double>>;

/// Nodal stress tensors (9 components, row-major) and their von Mises values on the bottom,
/// middle and top surfaces, for the VTU.
std::vector<OwnedField> stress_fields(const shell::ShellModel& model, const Eigen::VectorXd& u,
                                      io::OutputSection::ShellStress kind) {
  std::vector<OwnedField> out;
  if (kind == io::OutputSection::ShellStress::none) return out;
  const bool cauchy = kind == io::OutputSection::ShellStress::cauchy;
  const auto measure =
      cauchy ? shell::StressMeasure::cauchy : shell::StressMeasure::second_piola_kirchhoff;
  const std::string prefix = cauchy ? "cauchy_stress" : "pk2_stress";
  for (const auto& [side, side_name] : {std::pair{shell::SurfaceSide::bottom, "bottom"},
                                        std::pair{shell::SurfaceSide::middle, "middle"},
                                        std::pair{shell::SurfaceSide::top, "top"}}) {
    const shell::NodalStresses nodal = shell::nodal_stresses(model, u, measure, side);
    std::vector<double> tensor(9 * nodal.tensor.size());
    for (std::size_t k = 0; k < nodal.tensor.size(); ++k)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          tensor[9 * k + static_cast<std::size_t>(3 * i + j)] = nodal.tensor[k](i, j);
    out.emplace_back(fmt::format("{}_{}", prefix, side_name), 9, std::move(tensor));
    out.emplace_back(fmt::format("von_mises_{}", side_name), 1, nodal.von_mises);
  }
  return out;
}

}  // namespace

void run_shell(const io::Case& c, const io::CaseMeshes& meshes, io::ProbeSet& probes,
               std::span<const io::FieldView> initial_fields, const std::filesystem::path& outdir) {
  const io::ShellSection& s = *c.shell;
  const io::ShellAnalysis& analysis = *s.analysis;
  const mesh::Mesh& mesh = *meshes.shell;
  shell::ShellModel model = build_model(s, mesh);
  const Index n = mesh.num_nodes();
  io::PvdWriter pvd(outdir, "shell");

  // Records probes and (every output.every steps) fields of state u, v at time / level t.
  auto record = [&](long step, double t, const Eigen::VectorXd& u, const Eigen::VectorXd* v,
                    bool write_fields) {
    const auto displacement = nodal_part(u, n, 0);
    std::vector<double> director = nodal_part(u, n, 3);
    for (Index k = 0; k < n; ++k)
      for (int i = 0; i < 3; ++i)
        director[3 * static_cast<std::size_t>(k) + static_cast<std::size_t>(i)] +=
            model.directors()[static_cast<std::size_t>(k)][i];
    std::vector<double> position(3 * static_cast<std::size_t>(n)),
        thickness(static_cast<std::size_t>(n));
    for (Index k = 0; k < n; ++k) {
      for (int i = 0; i < 3; ++i)
        position[3 * static_cast<std::size_t>(k) + static_cast<std::size_t>(i)] =
            mesh.nodes[static_cast<std::size_t>(k)][i] +
            displacement[3 * static_cast<std::size_t>(k) + static_cast<std::size_t>(i)];
      thickness[static_cast<std::size_t>(k)] = u[shell::dofs_per_node * k + 6];
    }
    const std::vector<double> velocity =
        v ? nodal_part(*v, n, 0) : std::vector<double>(3 * static_cast<std::size_t>(n), 0.0);
    std::vector<io::FieldView> fields;
    for (const auto& f : initial_fields)
      if (f.mesh != "shell") fields.push_back(f);
    fields.push_back({"shell", "displacement", 3, displacement});
    fields.push_back({"shell", "velocity", 3, velocity});
    fields.push_back({"shell", "position", 3, position});
    probes.record(t, fields);
    if (!write_fields) return;
    std::vector<Vec3> x(static_cast<std::size_t>(n));
    for (Index k = 0; k < n; ++k)
      x[static_cast<std::size_t>(k)] = Vec3(position[3 * static_cast<std::size_t>(k)],
                                            position[3 * static_cast<std::size_t>(k) + 1],
                                            position[3 * static_cast<std::size_t>(k) + 2]);
    const std::string name = fmt::format("shell_{:06}.vtu", step);
    std::vector<io::VtuField> vtu_fields = {{"displacement", 3, displacement},
                                            {"velocity", 3, velocity},
                                            {"director", 3, director},
                                            {"thickness_parameter", 1, thickness}};
    const std::vector<OwnedField> stress = stress_fields(model, u, c.output.shell_stress);
    for (const auto& [field_name, components, values] : stress)
      vtu_fields.push_back({field_name, components, values});
    io::write_mesh_vtu(outdir / name, mesh, std::move(vtu_fields), t, x);
    pvd.add(t, name);
  };

  if (analysis.type == io::ShellAnalysisType::static_load) {
    shell::NewtonOptions newton;
    newton.modified = analysis.modified_newton;
    shell::StaticSolver solver(model, newton);
    record(0, 0.0, solver.displacement(), nullptr, true);
    long step = 0;
    auto on_level = [&](const shell::LoadStep& level, bool last) {
      ++step;
      spdlog::info("load factor {:.6g}: converged in {} Newton iterations", level.load_factor,
                   level.iterations);
      record(step, level.load_factor, solver.displacement(), nullptr,
             step % c.output.every == 0 || last);
    };
    try {
      switch (analysis.control) {
        case io::PathControl::load:
          solver.run(analysis.steps, 1.0, [&](const shell::LoadStep& level) {
            on_level(level, level.load_factor >= 1.0 - 1e-12);
          });
          break;
        case io::PathControl::displacement: {
          shell::ControlledDisplacement control;
          control.node = analysis.controlled_node;
          control.group = analysis.controlled_group;
          control.component = analysis.controlled_component;
          if (control.node >= n) {
            throw_at(analysis.where, fmt::format("controlled node {} does not exist: the shell "
                                                 "mesh has nodes 0 to {}",
                                                 control.node, n - 1));
          }
          long level_count = 0;
          solver.run_displacement_control(control, analysis.steps, analysis.final_displacement,
                                          [&](const shell::LoadStep& level) {
                                            on_level(level, ++level_count == analysis.steps);
                                          });
          break;
        }
        case io::PathControl::arc_length: {
          shell::ArcLengthOptions options;
          options.initial_load_increment = analysis.initial_load_increment;
          long level_count = 0;
          const auto levels =
              solver.run_arc_length(analysis.steps, options, [&](const shell::LoadStep& level) {
                const bool done = level.load_factor >= analysis.final_load_factor;
                on_level(level, done || ++level_count == analysis.steps);
                return !done;
              });
          if (levels.empty() || levels.back().load_factor < analysis.final_load_factor) {
            spdlog::warn(
                "arc length: load factor {:.6g} after {} steps, short of the final "
                "load factor {}; raise analysis.steps",
                levels.empty() ? 0.0 : levels.back().load_factor, levels.size(),
                analysis.final_load_factor);
          }
          break;
        }
      }
    } catch (const SolverError& e) {
      record(step + 1, solver.load_factor(), solver.displacement(), nullptr, true);
      throw SolverError(fmt::format("{}; the last converged state (load factor {:.6g}) is in {}",
                                    e.what(), solver.load_factor(), outdir.string()));
    }
    return;
  }

  const TimeFunction load_function = analysis.load_function;
  shell::NewmarkOptions options;
  options.mass_damping = analysis.mass_damping;
  options.newton.modified = analysis.modified_newton;
  options.scheme = analysis.scheme == io::TimeScheme::midpoint ? shell::TimeScheme::midpoint
                                                               : shell::TimeScheme::newmark;
  shell::NewmarkSolver solver(model, options, [&](double t) { return load_function.value(t); });
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_dofs());
  solver.set_initial_state(zero, zero);
  record(0, 0.0, solver.displacement(), &solver.velocity(), true);
  const double dt = c.time->step;
  const auto steps = static_cast<long>(std::llround(c.time->end / dt));
  Progress progress(0.0, c.time->end);
  for (long step = 1; step <= steps; ++step) {
    try {
      solver.advance(dt);
    } catch (const SolverError& e) {
      // The solver keeps the last converged state: write it before reporting.
      record(step, solver.time(), solver.displacement(), &solver.velocity(), true);
      throw SolverError(fmt::format("{}; the last converged state (t = {:.6g} s) is in {}",
                                    e.what(), solver.time(), outdir.string()));
    }
    record(step, solver.time(), solver.displacement(), &solver.velocity(),
           step % c.output.every == 0 || step == steps);
    progress.update(solver.time(), step);
  }
  progress.finish();
}

}  // namespace shellflow::app
