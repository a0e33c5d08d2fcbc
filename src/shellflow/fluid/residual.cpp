#include "shellflow/fluid/residual.h"

#include <algorithm>

#include "shellflow/fluid/element_kernel.h"

namespace shellflow::fluid {

namespace {

// Two elements per step of the element pass, one per lane of an SSE2 register (the x86-64
// baseline): the kernel's arithmetic runs on packs, gathers and scatters stay scalar.
using Pack = double __attribute__((vector_size(16)));
constexpr int pack_lanes = 2;

}  // namespace

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
  // Local stepping: the first-order rows get the nodal dt_a when scattered.
  const Pack dt = Pack{} + (local ? 1.0 : p.dt);
  for_each_block(loop, [&](Index first, Index last) {
    for (Index e0 = first; e0 < last; e0 += pack_lanes) {
      // A short last pack repeats its last element in the idle lanes (not scattered).
      const int count = static_cast<int>(std::min<Index>(pack_lanes, last - e0));
      detail::ElementData<Pack> s;
      Pack viscosity, dt_element;
      Index nodes[pack_lanes][4];
      for (int l = 0; l < pack_lanes; ++l) {
        const auto e = std::size_t(e0 + std::min(l, count - 1));
        s.volume[l] = g.volume[e];
        const auto& b = g.grad[e];
        for (int a = 0; a < 4; ++a) {
          for (int j = 0; j < 3; ++j) s.grad[a][j][l] = b[std::size_t(3 * a + j)];
          const Index n = loop.tets[4 * e + std::size_t(a)];
          nodes[l][a] = n;
          for (int v = 0; v < num_variables; ++v)
            s.u[a][v][l] = u.var[std::size_t(v)][std::size_t(n)];
          if (k.mesh_moves)
            for (int j = 0; j < 3; ++j) s.w[a][j][l] = w[std::size_t(n)][j];
        }
        viscosity[l] = has_viscosity ? element_viscosity[e] : 0.0;
        dt_element[l] = local ? p.element_dt[e] : p.dt;
      }
      detail::compute_element(k, s);
      Pack value[4][num_variables];
      detail::element_contributions(k, s, viscosity, dt, dt_element, value);
      for (int l = 0; l < count; ++l)
        for (int a = 0; a < 4; ++a) {
          const auto node = std::size_t(nodes[l][a]);
          const double f = local ? p.nodal_dt[node] : 1.0;
          for (int v = 0; v < num_variables; ++v)
            out[std::size_t(v)][node] += local ? f * value[a][v][l] : value[a][v][l];
        }
    }
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
