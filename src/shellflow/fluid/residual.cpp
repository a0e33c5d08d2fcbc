#include "shellflow/fluid/residual.h"

#include "shellflow/fluid/element_kernel.h"

namespace shellflow::fluid {

void assemble_residual(const ResidualParameters& p, const ElementLoop& loop,
                       const TetGeometry& g, const FluidState& u, std::span<const Vec3> w,
                       std::span<const double> element_viscosity, FluidState& r) {
  r.fill_zero();
  const detail::KernelConstants k{p.gas.gamma - 1.0, p.dt,
                                  p.tg_velocity == TgVelocity::relative,
                                  p.moving_mesh_correction, p.mesh_moves};
  const bool has_viscosity = !element_viscosity.empty();
  const bool local = !p.nodal_dt.empty();
  std::array<double*, num_variables> out{};
  for (int v = 0; v < num_variables; ++v) out[std::size_t(v)] = r.var[std::size_t(v)].data();
  for_each_element(loop, [&](Index e) {
    detail::ElementState s;
    detail::load_element(loop.tets, e, g, u, w, k.mesh_moves, s);
    detail::compute_element(k, s);
    const double dt_e = local ? p.element_dt[std::size_t(e)] : p.dt;
    detail::scatter_element(k, s, has_viscosity ? element_viscosity[std::size_t(e)] : 0.0, dt_e,
                            local ? p.nodal_dt.data() : nullptr, out);
  });
}

Vec3 face_area_vector(std::span<const Vec3> x, const BoundaryFace& f) {
  const Vec3& x0 = x[std::size_t(f.nodes[0])];
  Vec3 a = 0.5 * (x[std::size_t(f.nodes[1])] - x0).cross(x[std::size_t(f.nodes[2])] - x0);
  if (a.dot(x0 - x[std::size_t(f.opposite_node)]) < 0.0) a = -a;
  return a;
}

void add_natural_boundary_term(const ResidualParameters& p, const ElementLoop& loop,
                               std::span<const Vec3> x, const TetGeometry& g,
                               const FluidState& u, std::span<const Vec3> w,
                               std::span<const BoundaryFace> faces, FluidState& r) {
  const detail::KernelConstants k{p.gas.gamma - 1.0, p.dt,
                                  p.tg_velocity == TgVelocity::relative,
                                  p.moving_mesh_correction, p.mesh_moves};
  // Serial: boundary faces are few, and faces of different elements share nodes.
  for (const auto& f : faces) {
    detail::ElementState s;
    detail::load_element(loop.tets, f.element, g, u, w, k.mesh_moves, s);
    detail::compute_element(k, s);
    const Vec3 area = face_area_vector(x, f);
    const bool local = !p.nodal_dt.empty();
    const double dt_e = local ? p.element_dt[std::size_t(f.element)] : p.dt;
    for (int v = 0; v < num_variables; ++v) {
      double flux = 0.0;
      for (int j = 0; j < 3; ++j) flux += area[j] * s.tg_flux[j][v];
      for (const Index a : f.nodes) {
        const double dt_a = local ? p.nodal_dt[std::size_t(a)] : p.dt;
        r.var[std::size_t(v)][std::size_t(a)] += -0.5 * dt_a * dt_e / 3.0 * flux;
      }
    }
  }
}

}  // namespace shellflow::fluid
