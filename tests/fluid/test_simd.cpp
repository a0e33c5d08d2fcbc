// The element pass's instruction sets (residual.h, SimdPath): AVX2 gives the bits of the
// SSE2 reference, AVX2 with FMA differs only by rounding, and every set keeps a uniform state
// exactly uniform.
#include <gtest/gtest.h>

#include <random>

#include "fluid_test_util.h"
#include "shellflow/core/error.h"
#include "shellflow/fluid/ordering.h"
#include "shellflow/fluid/residual.h"

using namespace shellflow;
using namespace shellflow::fluid;

namespace {

/// A jittered unit cube in block order (blocks of 29 cells: short packs at block ends), a
/// smooth non-uniform state, random mesh velocities and element viscosities.
struct PassSetup {
  mesh::Mesh mesh = test_support::case_mesh("unit_cube.geo");
  CellColouring colours;
  std::vector<Index> tets;
  TetGeometry g;
  FluidState u;
  std::vector<Vec3> w;
  std::vector<double> viscosity, element_dt, nodal_dt;

  PassSetup() {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> jitter(-0.02, 0.02), speed(-2.0, 2.0), nu(0.0, 0.1);
    for (auto& x : mesh.nodes)
      if (x.minCoeff() > 1e-9 && x.maxCoeff() < 1 - 1e-9) x += Vec3(jitter(rng), jitter(rng), jitter(rng));
    colours = colour_cells(mesh.cells.connectivity, 4, mesh.num_nodes(), 29);
    for (const Index c : colours.order) {
      const auto cell = mesh.cells.element(c);
      tets.insert(tets.end(), cell.begin(), cell.end());
    }
    compute_geometry(mesh.nodes, tets, g);
    IdealGas gas;
    u.resize(mesh.num_nodes());
    for (Index a = 0; a < mesh.num_nodes(); ++a) {
      const Vec3& x = mesh.nodes[std::size_t(a)];
      u.set(a, to_conservative(
                   gas, {1.2 + 0.3 * std::sin(3 * x.x()), Vec3(2.1 + x.y(), 0.4 - x.z() * x.x(), -0.3 + 0.5 * x.y()),
                         0.9 + 0.2 * std::cos(2 * x.z())}));
    }
    w.resize(mesh.nodes.size());
    for (auto& v : w) v = Vec3(speed(rng), speed(rng), speed(rng));
    viscosity.resize(std::size_t(mesh.num_cells()));
    for (auto& v : viscosity) v = nu(rng);
    element_dt.resize(viscosity.size());
    for (auto& d : element_dt) d = 1e-3 * (1.0 + nu(rng));
    nodal_dt.assign(mesh.nodes.size(), 1e-3);
  }

  ElementLoop loop() const { return {tets, colours.block_offsets, colours.colour_offsets}; }

  FluidState residual(SimdPath path, bool moves, bool local, const FluidState& state) const {
    set_simd_path(path);
    ResidualParameters p;
    p.dt = 1e-3;
    p.mesh_moves = moves;
    if (local) {
      p.element_dt = element_dt;
      p.nodal_dt = nodal_dt;
    }
    FluidState r;
    r.resize(mesh.num_nodes());
    assemble_residual(p, loop(), g, state, w, viscosity, r);
    return r;
  }
};

std::vector<SimdPath> paths_of_this_cpu() {
  std::vector<SimdPath> paths{SimdPath::sse2};
  if (__builtin_cpu_supports("avx2")) paths.push_back(SimdPath::avx2);
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) paths.push_back(SimdPath::avx2_fma);
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") &&
      __builtin_cpu_supports("fma"))
    paths.push_back(SimdPath::avx512);
  return paths;
}

/// Puts the process's choice back after the test.
struct KeepSimdPath {
  SimdPath saved = simd_path();
  ~KeepSimdPath() { set_simd_path(saved); }
};

}  // namespace

TEST(SimdPath, Avx2GivesTheBitsOfSse2AndFmaOnlyRoundsDifferently) {
  const auto paths = paths_of_this_cpu();
  if (paths.size() < 3) GTEST_SKIP() << "this CPU has no AVX2 and FMA";
  const KeepSimdPath keep;
  const PassSetup s;
  for (const bool moves : {false, true})
    for (const bool local : {false, true}) {
      const FluidState ref = s.residual(SimdPath::sse2, moves, local, s.u);
      const FluidState avx = s.residual(SimdPath::avx2, moves, local, s.u);
      for (int v = 0; v < num_variables; ++v)
        for (std::size_t a = 0; a < ref.var[std::size_t(v)].size(); ++a)
          ASSERT_EQ(avx.var[std::size_t(v)][a], ref.var[std::size_t(v)][a]) << "row " << v << " node " << a;
      for (const SimdPath fused : paths) {
        if (fused == SimdPath::sse2 || fused == SimdPath::avx2) continue;
        const FluidState fma = s.residual(fused, moves, local, s.u);
        double scale = 0.0, fma_diff = 0.0;
        int fma_differs = 0;
        for (int v = 0; v < num_variables; ++v)
          for (std::size_t a = 0; a < ref.var[std::size_t(v)].size(); ++a) {
            const double x = ref.var[std::size_t(v)][a];
            scale = std::max(scale, std::abs(x));
            const double d = std::abs(fma.var[std::size_t(v)][a] - x);
            fma_diff = std::max(fma_diff, d);
            fma_differs += d > 0.0;
          }
        EXPECT_GT(scale, 0.0);
        // Contraction changes the rounding of each product-sum: differences of a few ulps of
        // the largest terms, relative to the largest residual.
        EXPECT_LT(fma_diff, 1e-12 * scale) << to_string(fused) << " moves " << moves << " local " << local;
        // The FMA variant is really a different instruction sequence.
        EXPECT_GT(fma_differs, 0) << to_string(fused);
      }
    }
}

TEST(SimdPath, EverySetKeepsAUniformStateExactlyUniform) {
  const KeepSimdPath keep;
  PassSetup s;
  IdealGas gas;
  FluidState uniform;
  uniform.resize(s.mesh.num_nodes());
  const Conservative q = to_conservative(gas, {1.2, Vec3(2.1, 0.4, -0.3), 0.9});
  for (Index a = 0; a < s.mesh.num_nodes(); ++a) uniform.set(a, q);
  for (const SimdPath path : paths_of_this_cpu())
    for (const bool local : {false, true}) {
      const FluidState r = s.residual(path, true, local, uniform);
      for (int v = 0; v < num_variables; ++v)
        for (const double x : r.var[std::size_t(v)]) ASSERT_EQ(x, 0.0) << to_string(path);
    }
}

TEST(SimdPath, NamesParseAndBadNamesSayWhatToUse) {
  EXPECT_EQ(parse_simd_path("sse2", "test"), SimdPath::sse2);
  for (const SimdPath path : paths_of_this_cpu()) EXPECT_EQ(parse_simd_path(to_string(path), "test"), path);
  EXPECT_EQ(parse_simd_path("auto", "test"), paths_of_this_cpu().back());
  try {
    parse_simd_path("avx9\n", "environment variable SHELLFLOW_SIMD");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "environment variable SHELLFLOW_SIMD: unknown instruction set 'avx9\\x0a'; use "
                 "auto, sse2, avx2, avx2-fma or avx512");
  }
}
