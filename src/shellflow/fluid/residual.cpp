#include "shellflow/fluid/residual.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>

#include "shellflow/core/error.h"
#include "shellflow/fluid/element_kernel.h"

namespace shellflow::fluid {

namespace {

// The element pass runs W elements at once, one per lane of a pack of W doubles; the kernel's
// arithmetic runs on packs, gathers and scatters stay scalar and go in element order, so every
// lane does exactly the operations of the scalar kernel whatever W is. Four variants, chosen
// at run time (simd_path()): 2 lanes in SSE2 (the x86-64 baseline, the reference), 4 lanes in
// AVX2 (the same bits), 4 lanes in AVX2 with fused multiply-adds (rounding differs) and 8
// lanes in AVX-512 with fused multiply-adds.
template <int W>
struct PackType;
template <>
struct PackType<2> {
  using type = double __attribute__((vector_size(16)));
};
template <>
struct PackType<4> {
  using type = double __attribute__((vector_size(32)));
};
template <>
struct PackType<8> {
  using type = double __attribute__((vector_size(64)));
};

struct PassInput {
  const ElementLoop& loop;
  const TetGeometry& g;
  const FluidState& u;
  std::span<const Vec3> w;
  std::span<const double> element_viscosity;
  std::span<const double> element_dt, nodal_dt;
  detail::KernelConstants k;
  double dt;
  std::array<double*, num_variables> out;
};

template <int W>
[[gnu::always_inline]] inline void pass_block(const PassInput& in, Index first, Index last) {
  using Pack = typename PackType<W>::type;
  const auto& k = in.k;
  const bool has_viscosity = !in.element_viscosity.empty();
  const bool local = !in.nodal_dt.empty();
  // Local stepping: the first-order rows get the nodal dt_a when scattered.
  const Pack dt = Pack{} + (local ? 1.0 : in.dt);
  for (Index e0 = first; e0 < last; e0 += W) {
    // A short last pack repeats its last element in the idle lanes (not scattered).
    const int count = static_cast<int>(std::min<Index>(W, last - e0));
    detail::ElementData<Pack> s;
    Pack viscosity, dt_element;
    Index nodes[W][4];
    for (int l = 0; l < W; ++l) {
      const auto e = std::size_t(e0 + std::min(l, count - 1));
      s.volume[l] = in.g.volume[e];
      const auto& b = in.g.grad[e];
      for (int a = 0; a < 4; ++a) {
        for (int j = 0; j < 3; ++j) s.grad[a][j][l] = b[std::size_t(3 * a + j)];
        const Index n = in.loop.tets[4 * e + std::size_t(a)];
        nodes[l][a] = n;
        for (int v = 0; v < num_variables; ++v) s.u[a][v][l] = in.u.var[std::size_t(v)][std::size_t(n)];
        if (k.mesh_moves)
          for (int j = 0; j < 3; ++j) s.w[a][j][l] = in.w[std::size_t(n)][j];
      }
      viscosity[l] = has_viscosity ? in.element_viscosity[e] : 0.0;
      dt_element[l] = local ? in.element_dt[e] : in.dt;
    }
    detail::compute_element(k, s);
    Pack value[4][num_variables];
    detail::element_contributions(k, s, viscosity, dt, dt_element, value);
    for (int l = 0; l < count; ++l)
      for (int a = 0; a < 4; ++a) {
        const auto node = std::size_t(nodes[l][a]);
        const double f = local ? in.nodal_dt[node] : 1.0;
        for (int v = 0; v < num_variables; ++v)
          in.out[std::size_t(v)][node] += local ? f * value[a][v][l] : value[a][v][l];
      }
  }
}

// One function per instruction set, everything inlined into it (flatten) so that the kernel
// is compiled for that set. The parallel loop stays outside, in the baseline code.
[[gnu::flatten]] void pass_block_sse2(const PassInput& in, Index first, Index last) { pass_block<2>(in, first, last); }
[[gnu::flatten, gnu::target("avx2")]] void pass_block_avx2(const PassInput& in, Index first, Index last) {
  pass_block<4>(in, first, last);
}
// The project builds as ISO C++ (no contraction); this variant asks for it.
[[gnu::flatten, gnu::target("avx2,fma"), gnu::optimize("fp-contract=fast")]] void pass_block_avx2_fma(
    const PassInput& in, Index first, Index last) {
  pass_block<4>(in, first, last);
}
[[gnu::flatten, gnu::target("avx512f,avx512dq,avx512vl,avx2,fma"), gnu::optimize("fp-contract=fast")]] void
pass_block_avx512(const PassInput& in, Index first, Index last) {
  pass_block<8>(in, first, last);
}

bool cpu_has(SimdPath path) {
  switch (path) {
    case SimdPath::sse2:
      return true;
    case SimdPath::avx2:
      return __builtin_cpu_supports("avx2");
    case SimdPath::avx2_fma:
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case SimdPath::avx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
             __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }
  return false;
}

SimdPath best_path() {
  return cpu_has(SimdPath::avx512)     ? SimdPath::avx512
         : cpu_has(SimdPath::avx2_fma) ? SimdPath::avx2_fma
         : cpu_has(SimdPath::avx2)     ? SimdPath::avx2
                                       : SimdPath::sse2;
}

std::atomic<int>& chosen_path() {
  static std::atomic<int> path = -1;  // -1: not chosen yet
  return path;
}

}  // namespace

std::string_view to_string(SimdPath path) {
  switch (path) {
    case SimdPath::sse2:
      return "sse2";
    case SimdPath::avx2:
      return "avx2";
    case SimdPath::avx2_fma:
      return "avx2-fma";
    case SimdPath::avx512:
      return "avx512";
  }
  return "?";
}

SimdPath parse_simd_path(std::string_view name, std::string_view origin) {
  if (name == "auto") return best_path();
  for (const SimdPath path : {SimdPath::sse2, SimdPath::avx2, SimdPath::avx2_fma, SimdPath::avx512})
    if (name == to_string(path)) {
      if (!cpu_has(path)) throw_input_error("{}: this CPU has no {}; use auto or sse2", origin, to_string(path));
      return path;
    }
  throw_input_error("{}: unknown instruction set '{}'; use auto, sse2, avx2, avx2-fma or avx512", origin,
                    printable(name.substr(0, 40)) + (name.size() > 40 ? "..." : ""));
}

SimdPath simd_path() {
  int path = chosen_path().load(std::memory_order_relaxed);
  if (path < 0) {
    const char* env = std::getenv("SHELLFLOW_SIMD");
    const SimdPath p = env ? parse_simd_path(env, "environment variable SHELLFLOW_SIMD") : best_path();
    path = static_cast<int>(p);
    chosen_path().store(path, std::memory_order_relaxed);
  }
  return static_cast<SimdPath>(path);
}

void set_simd_path(SimdPath path) {
  if (!cpu_has(path)) throw_input_error("instruction set {}: this CPU does not have it", to_string(path));
  chosen_path().store(static_cast<int>(path), std::memory_order_relaxed);
}

void assemble_residual(const ResidualParameters& p, const ElementLoop& loop, const TetGeometry& g, const FluidState& u,
                       std::span<const Vec3> w, std::span<const double> element_viscosity, FluidState& r) {
  r.fill_zero();
  PassInput in{loop,
               g,
               u,
               w,
               element_viscosity,
               p.element_dt,
               p.nodal_dt,
               {p.gas.gamma - 1.0, p.dt, p.tg_velocity == TgVelocity::relative, p.moving_mesh_correction, p.mesh_moves},
               p.dt,
               {}};
  if (!p.nodal_dt.empty() && p.element_dt.empty())
    throw Error("assemble_residual: local stepping needs element and nodal steps");
  for (int v = 0; v < num_variables; ++v) in.out[std::size_t(v)] = r.var[std::size_t(v)].data();
  using Block = void (*)(const PassInput&, Index, Index);
  Block block = pass_block_sse2;
  switch (simd_path()) {
    case SimdPath::sse2:
      break;
    case SimdPath::avx2:
      block = pass_block_avx2;
      break;
    case SimdPath::avx2_fma:
      block = pass_block_avx2_fma;
      break;
    case SimdPath::avx512:
      block = pass_block_avx512;
      break;
  }
  for_each_block(loop, [&](Index first, Index last) { block(in, first, last); });
}

Vec3 face_area_vector(std::span<const Vec3> x, const BoundaryFace& f) {
  const Vec3& x0 = x[std::size_t(f.nodes[0])];
  Vec3 a = 0.5 * (x[std::size_t(f.nodes[1])] - x0).cross(x[std::size_t(f.nodes[2])] - x0);
  if (a.dot(x0 - x[std::size_t(f.opposite_node)]) < 0.0) a = -a;
  return a;
}

void add_natural_boundary_term(const ResidualParameters& p, const ElementLoop& loop, std::span<const Vec3> x,
                               const TetGeometry& g, const FluidState& u, std::span<const Vec3> w,
                               std::span<const BoundaryFace> faces, FluidState& r) {
  const detail::KernelConstants k{p.gas.gamma - 1.0, p.dt, p.tg_velocity == TgVelocity::relative,
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
