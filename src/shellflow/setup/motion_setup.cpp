#include "shellflow/setup/motion_setup.h"

#include <spdlog/spdlog.h>

#include "shellflow/core/error.h"
#include "shellflow/motion/laplace_mover.h"

namespace shellflow::setup {

motion::SpaceMeshOptions space_mesh_options(const io::MotionSection& m) {
  motion::SpaceMeshOptions options;
  options.interface_groups = m.interface_groups;
  options.fixed_groups = m.fixed_groups;
  options.sliding_groups = m.sliding_groups;
  options.interface_exponent = m.interface_exponent;
  options.fixed_exponent = m.fixed_exponent;
  options.weighting =
      m.weighting == io::MotionWeighting::area ? motion::IdwWeighting::area : motion::IdwWeighting::plain;
  return options;
}

std::unique_ptr<motion::PanelModesMotion> prescribed_motion(const io::MotionSection& m) {
  if (!m.prescribed) {
    throw_at(m.where,
             "a mesh-motion run needs 'prescribed' (the boundary motion) until a shell "
             "solver drives it");
  }
  const auto& p = *m.prescribed;
  std::vector<motion::PanelModesMotion::Mode> modes;
  for (const auto& mode : p.modes) modes.push_back({mode.wave_number, mode.amplitude});
  return std::make_unique<motion::PanelModesMotion>(p.leading_edge, p.direction, p.length, p.normal, std::move(modes));
}

std::unique_ptr<motion::FluidMeshMover> build_mover(const io::MotionSection& m, const io::CaseMeshes& meshes,
                                                    motion::BoundaryMotion& boundary) {
  const auto weighting =
      m.weighting == io::MotionWeighting::area ? motion::IdwWeighting::area : motion::IdwWeighting::plain;
  const mesh::Mesh& fluid = *meshes.fluid;
  switch (m.method) {
    case io::MotionMethod::space_mesh: {
      const motion::SpaceMeshOptions options = space_mesh_options(m);
      // IDW samples: the shell's nodes when the case has a shell mesh (the paper's sums),
      // else the fluid mesh's interface nodes.
      std::vector<Vec3> samples;
      std::vector<double> areas;
      if (meshes.shell) {
        samples = meshes.shell->nodes;
        areas = motion::lumped_node_areas(meshes.shell->nodes, meshes.shell->cells);
      }
      auto mover = std::make_unique<motion::SpaceMeshMover>(fluid, *meshes.space, options, boundary, samples, areas);
      const auto& r = mover->location_report();
      spdlog::info(
          "space mesh: located {} fluid nodes (max residual {:.2e} m, {} Newton "
          "iterations at most), {} projected from outside (max gap {:.2e} m)",
          r.located, r.max_residual, r.max_newton_iterations, r.projected, r.max_gap);
      return mover;
    }
    case io::MotionMethod::direct_idw:
      return std::make_unique<motion::DirectIdwMover>(
          fluid, motion::BoundaryGroups{m.interface_groups, m.fixed_groups, m.sliding_groups}, boundary,
          m.interface_exponent, m.fixed_exponent, weighting);
    case io::MotionMethod::laplace:
      return std::make_unique<motion::LaplaceMover>(
          fluid, motion::BoundaryGroups{m.interface_groups, m.fixed_groups, m.sliding_groups}, boundary);
  }
  throw Error("unknown motion method");
}

}  // namespace shellflow::setup
