// Per-update cost of the fluid mesh movers (motion.md; issue 5 "Performance"): the space
// mesh (the paper's method), direct IDW on every fluid node and Laplacian smoothing (CG +
// incomplete Cholesky, warm-started), on the panel-flutter slab refined to about 1e4, 8e4,
// 1e5 and 1e6 fluid nodes (1e6: ten element layers across the slab, see refined_slab),
// with the space mesh kept at cases/panel_flutter/space_mesh.geo (~1 000 nodes) and the
// shell's nodes as IDW samples. Direct IDW and the Laplacian are not run at 1e6 nodes (each
// update would take minutes). Each iteration advances the single-mode panel motion
// A sin(2 pi 30 t) sin(pi s / L), A = 2 cm, by 1e-5 s (a fluid sub-step), so the Laplacian
// solves are warm-started as in a run (three untimed updates first: the timings are of
// steady, warm-started steps, not of the first, cold solve).
//
// Counters: fluid nodes and tetrahedra, mover memory (memory_bytes(), MB), one-off set-up
// time of the mover (space mesh: classification + IDW weights + location of every fluid
// node), and for the Laplacian the largest CG iteration count of the last update. "Stream"
// is the reference: one pass reading 3 doubles and writing 3 doubles per fluid node.
// On a shared machine run with OMP_WAIT_POLICY=passive.
//
//   build/release/bench/motion/bench_mesh_motion --benchmark_min_time=0.2
//   build/release/bench/motion/bench_mesh_motion --benchmark_filter=SpaceMeshUpdate
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include "shellflow/core/version.h"
#include "shellflow/mesh/gmsh_io.h"
#include "shellflow/motion/laplace_mover.h"
#include "shellflow/motion/mesh_mover.h"

using namespace shellflow;
using namespace shellflow::motion;

namespace {

const std::filesystem::path panel_dir = std::filesystem::path(source_dir) / "cases" / "panel_flutter";
constexpr double kNodesAtUnitSize = 8622.0;  // fluid_slab.geo at size_factor 1
constexpr double kTimeStep = 1e-5;

mesh::Mesh generate(const char* geo, int order, double size_factor, const char* name) {
  mesh::MeshingOptions options;
  options.order = order;
  options.size_factor = size_factor;
  return mesh::generate_mesh(panel_dir / geo, options, name);
}

const mesh::Mesh& space_mesh() {
  static const auto m = generate("space_mesh.geo", 3, 1.0, "space");
  return m;
}
const mesh::Mesh& shell_mesh() {
  static const auto m = generate("panel_strip.geo", 3, 1.0, "shell");
  return m;
}

BoundaryGroups panel_groups() { return {{"panel"}, {"inflow", "outflow", "far_field", "wall"}, {"symmetry"}}; }

/// One fluid mesh size, with its movers built on first use and kept for the whole run
/// (Google Benchmark calls a benchmark function several times).
struct Setup {
  mesh::Mesh fluid;
  PanelModesMotion motion{Vec3(0.25, 0, 0), Vec3::UnitX(), 0.5, Vec3::UnitY(), {{1, TimeFunction::sine(0.02, 30.0)}}};
  std::unique_ptr<FluidMeshMover> space, direct, laplace;
  double space_setup_s = 0, direct_setup_s = 0, laplace_setup_s = 0;
  std::vector<Vec3> x, w;
  double time = 0.0;
};

/// `slab` (a one-layer extruded slab 0 <= z <= width: every node on z = 0 or z = width)
/// stacked `layers` times, each copy squeezed to width / layers. The horizontal faces of the
/// extruded mesh are copies of one 2D triangulation, so the copies are conforming. Groups:
/// "symmetry" keeps the bottom facets of the first copy and the top facets of the last;
/// every other group is repeated in every copy.
mesh::Mesh stack_layers(const mesh::Mesh& slab, int layers, double width) {
  const auto n = slab.nodes.size();
  std::map<std::pair<double, double>, Index> point_of;  // (x, y) -> 2D point
  std::vector<Index> point(n);
  std::vector<int> level(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& X = slab.nodes[i];
    level[i] = X.z() > 0.5 * width ? 1 : 0;
    point[i] = point_of.try_emplace({X.x(), X.y()}, static_cast<Index>(point_of.size())).first->second;
  }
  const auto n2d = static_cast<Index>(point_of.size());
  if (2 * static_cast<std::size_t>(n2d) != n) throw std::runtime_error("stack_layers: not a one-layer slab");
  mesh::Mesh m;
  m.name = "fluid";
  m.source = slab.source + " (stacked)";
  m.nodes.resize(static_cast<std::size_t>(n2d) * static_cast<std::size_t>(layers + 1));
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = level[i]; k <= layers - 1 + level[i]; ++k) {
      const Vec3& X = slab.nodes[i];
      m.nodes[static_cast<std::size_t>(point[i] + k * n2d)] = Vec3(X.x(), X.y(), width * k / layers);
    }
  }
  m.node_tags.resize(m.nodes.size());
  for (std::size_t i = 0; i < m.nodes.size(); ++i) m.node_tags[i] = i + 1;
  auto copy = [&](const mesh::ElementBlock& from, int k, mesh::ElementBlock& to) {
    for (Index node : from.connectivity) {
      const auto i = static_cast<std::size_t>(node);
      to.connectivity.push_back(point[i] + (k + level[i]) * n2d);
    }
  };
  m.cells.type = slab.cells.type;
  for (int k = 0; k < layers; ++k) copy(slab.cells, k, m.cells);
  for (const auto& g : slab.groups) {
    mesh::PhysicalGroup h;
    h.name = g.name;
    h.dim = g.dim;
    h.tag = g.tag;
    if (g.dim == 3) {
      for (Index c = 0; c < m.num_cells(); ++c) h.cells.push_back(c);
      m.groups.push_back(std::move(h));
      continue;
    }
    h.elements.type = g.elements.type;
    if (g.name == "symmetry") {
      for (Index f = 0; f < g.elements.size(); ++f) {
        const auto facet = g.elements.element(f);
        const int l = level[static_cast<std::size_t>(facet[0])];
        mesh::ElementBlock one{g.elements.type, {facet.begin(), facet.end()}};
        copy(one, l == 0 ? 0 : layers - 1, h.elements);
      }
    } else {
      for (int k = 0; k < layers; ++k) copy(g.elements, k, h.elements);
    }
    h.nodes = h.elements.connectivity;
    std::sort(h.nodes.begin(), h.nodes.end());
    h.nodes.erase(std::unique(h.nodes.begin(), h.nodes.end()), h.nodes.end());
    m.groups.push_back(std::move(h));
  }
  return m;
}

/// The panel slab with about `target_nodes` fluid nodes. Up to ~1e5 nodes: the one-layer slab
/// with its sizes scaled by size_factor (nodes ~ 8 622 / size_factor^2). Beyond: a coarser
/// one-layer slab stacked in 10 layers (Gmsh's splitting of a finely extruded mesh into
/// tetrahedra takes many minutes at 1e6 nodes); the cells stay about isotropic (2.5 mm of
/// depth per layer against 2-3 mm in-plane).
mesh::Mesh refined_slab(int target_nodes) {
  const int layers = target_nodes > 200000 ? 10 : 1;
  const double per_plane = kNodesAtUnitSize / 2.0;
  mesh::MeshingOptions options;
  options.size_factor = std::sqrt(per_plane * (layers + 1) / target_nodes);
  auto slab = mesh::generate_mesh(panel_dir / "fluid_slab.geo", options, "fluid");
  return layers == 1 ? slab : stack_layers(slab, layers, 0.025);
}

Setup& setup(int target_nodes) {
  static std::map<int, std::unique_ptr<Setup>> cache;
  auto& s = cache[target_nodes];
  if (!s) {
    s = std::make_unique<Setup>();
    s->fluid = refined_slab(target_nodes);
    s->x.resize(s->fluid.nodes.size());
    s->w.resize(s->fluid.nodes.size());
  }
  return *s;
}

template <class Build>
FluidMeshMover& mover(std::unique_ptr<FluidMeshMover>& slot, double& seconds, Build build) {
  if (!slot) {
    const auto start = std::chrono::steady_clock::now();
    slot = build();
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return *slot;
}

SpaceMeshOptions space_options() {
  SpaceMeshOptions o;
  const auto g = panel_groups();
  o.interface_groups = g.interface_groups;
  o.fixed_groups = g.fixed_groups;
  o.sliding_groups = g.sliding_groups;
  return o;
}

void run(benchmark::State& st, Setup& s, FluidMeshMover& m, double setup_seconds, int untimed_updates = 0) {
  // The Laplacian solves are warm-started from the previous two updates: time steady steps.
  for (int i = 0; i < untimed_updates; ++i) {
    s.time += kTimeStep;
    m.update(s.time, s.x, s.w);
  }
  for (auto _ : st) {
    s.time += kTimeStep;
    m.update(s.time, s.x, s.w);
    benchmark::DoNotOptimize(s.x.data());
    benchmark::ClobberMemory();
  }
  st.counters["nodes"] = static_cast<double>(s.fluid.nodes.size());
  st.counters["tets"] = static_cast<double>(s.fluid.num_cells());
  st.counters["memory_MB"] = static_cast<double>(m.memory_bytes()) / 1e6;
  st.counters["setup_s"] = setup_seconds;
  if (const auto* l = dynamic_cast<const LaplaceMover*>(&m)) st.counters["cg_iterations"] = l->last_iterations();
}

void SpaceMeshUpdate(benchmark::State& st) {
  auto& s = setup(static_cast<int>(st.range(0)));
  auto& m = mover(s.space, s.space_setup_s, [&] {
    return std::make_unique<SpaceMeshMover>(s.fluid, space_mesh(), space_options(), s.motion, shell_mesh().nodes);
  });
  run(st, s, m, s.space_setup_s);
}

void DirectIdwUpdate(benchmark::State& st) {
  auto& s = setup(static_cast<int>(st.range(0)));
  auto& m = mover(s.direct, s.direct_setup_s,
                  [&] { return std::make_unique<DirectIdwMover>(s.fluid, panel_groups(), s.motion); });
  run(st, s, m, s.direct_setup_s);
}

void LaplaceUpdate(benchmark::State& st) {
  auto& s = setup(static_cast<int>(st.range(0)));
  auto& m = mover(s.laplace, s.laplace_setup_s,
                  [&] { return std::make_unique<LaplaceMover>(s.fluid, panel_groups(), s.motion); });
  run(st, s, m, s.laplace_setup_s, 3);
}

/// Reference: read 3 doubles and write 3 doubles per fluid node (the least any mover
/// that writes positions from per-node data can cost).
void Stream(benchmark::State& st) {
  auto& s = setup(static_cast<int>(st.range(0)));
  const auto& X = s.fluid.nodes;
  const auto n = static_cast<std::ptrdiff_t>(X.size());
  const Vec3 d(1e-3, 2e-3, 0.0);
  for (auto _ : st) {
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t p = 0; p < n; ++p) s.x[static_cast<std::size_t>(p)] = X[static_cast<std::size_t>(p)] + d;
    benchmark::DoNotOptimize(s.x.data());
    benchmark::ClobberMemory();
  }
  st.counters["nodes"] = static_cast<double>(n);
  st.SetBytesProcessed(static_cast<std::int64_t>(st.iterations()) * n * 48);
}

}  // namespace

// Order: stream first so that the mesh of each size is generated outside the timings.
BENCHMARK(Stream)->Arg(10000)->Arg(80000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(SpaceMeshUpdate)
    ->Arg(10000)
    ->Arg(80000)
    ->Arg(100000)
    ->Arg(1000000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// Direct IDW at 1e6 nodes: ~1e4 boundary nodes x 1e6 nodes = 1e10 weights per update
// (minutes; 8 s at 1e5 nodes): skipped.
BENCHMARK(DirectIdwUpdate)->Arg(10000)->Arg(80000)->Arg(100000)->Unit(benchmark::kMillisecond)->UseRealTime();
// Laplacian at 1e6 nodes: several hundred CG iterations x 4 solves per update on 1e6
// unknowns (iterations grow like 1/h; over a minute per update on the reference machine):
// skipped.
BENCHMARK(LaplaceUpdate)->Arg(10000)->Arg(80000)->Arg(100000)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
