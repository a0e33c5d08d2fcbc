// One fluid sub-step of the coupled flutter run, part by part, on the default panel slab
// (clamped_clamped.yaml: 8 622 nodes / 25 074 tetrahedra) and on its 4x and 16x refinements
// (meshes.fluid.size_factor 0.5 and 0.25), with 1 and 2 threads and the element pass in SSE2
// (simd:0, the reference), AVX2 with FMA (simd:2) and AVX-512 (simd:3):
//   BM_SubStep          shell steps of 34 sub-steps each (the default case's count), per
//                       sub-step: the space-mesh update (the shell's time modes moved once per
//                       shell step, combined per sub-step: FlowModel's mesh_seconds) and the
//                       flow step on the moved mesh (FlowModel's flow_seconds, with the
//                       stable-step check of each shell step), and inside it
//                       (fluid::StepTimings): artificial viscosity, element pass, update,
//                       geometry, normals, boundary conditions, checks;
//   BM_FixedSlabStep    the same flow step with the mesh at rest;
//   BM_SpaceMeshUpdate  the mover alone within one window: positions only (w = Δx/Δt, the
//                       default) and positions and velocities (mesh_velocity: interpolated).
// Every part as ns per tetrahedron and sub-step; the whole as M tet-updates/s.
//
//   OMP_WAIT_POLICY=passive build/release/bench/coupling/bench_substep [--benchmark_repetitions=3]
//
// The fixed-mesh step of the cube benchmark (bench/fluid/bench_fluid, FluidStep) runs in the
// same way; run both in one session to compare them.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <chrono>
#include <cmath>
#include <map>
#include <memory>

#include "shellflow/core/error.h"
#include "shellflow/core/version.h"
#include "shellflow/fluid/residual.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/setup/coupled_setup.h"

namespace {

using namespace shellflow;

struct Slab {
  io::Case c;
  io::CaseMeshes meshes;
  setup::CoupledSystem s;
  Eigen::VectorXd u0, v0, u1, v1;  ///< two shell states a step apart: the window of every sub-step
  double dt_f = 0.0;               ///< the sub-step
  explicit Slab(double size_factor)
      : c(io::read_case(std::filesystem::path(source_dir) / "cases" / "panel_flutter" / "clamped_clamped.yaml",
                        std::vector<io::KeyOverride>{
                            io::KeyOverride::parse(fmt::format("meshes.fluid.size_factor={}", size_factor))})),
        meshes(io::load_case_meshes(c, std::nullopt)),
        s(setup::build_coupled_system(c, meshes)) {
    // A moving panel: two shell steps of the start-up.
    s.driver->step(c.time->step);
    u0 = s.solver->displacement();
    v0 = s.solver->velocity();
    s.driver->step(c.time->step);
    u1 = s.solver->displacement();
    v1 = s.solver->velocity();
    dt_f = 0.9 * c.fluid->analysis->cfl * s.flow->flow()->stable_dt(1.0);  // one sub-step by the auto rule
  }
};

Slab& slab(double size_factor) {
  static std::map<double, std::unique_ptr<Slab>> slabs;
  auto& p = slabs[size_factor];
  if (!p) p = std::make_unique<Slab>(size_factor);
  return *p;
}

/// Sets the element pass's instruction set of argument `arg` (0 sse2, 1 avx2, 2 avx2-fma, 3 avx512);
/// false (and the benchmark skipped) when the CPU lacks it.
bool use_simd(benchmark::State& state, std::int64_t arg) {
  try {
    fluid::set_simd_path(fluid::SimdPath(arg));
  } catch (const Error& e) {
    state.SkipWithError(e.what());
    return false;
  }
  state.SetLabel(std::string(fluid::to_string(fluid::simd_path())));
  return true;
}

/// Per-tetrahedron figures of `steps` flow steps (0: one per iteration).
void per_tet_counters(benchmark::State& state, const Slab& sys, double mesh, double flow_s, double steps = 0.0) {
  const fluid::FluidModel& fluid = *sys.s.flow->flow();
  const double n = steps > 0.0 ? steps : double(state.iterations());
  const double tets = double(sys.s.fluid_mesh->num_cells());
  const auto per_tet = [&](double seconds) { return 1e9 * seconds / (n * tets); };
  const fluid::StepTimings& t = fluid.timings();
  state.counters["tets"] = tets;
  state.counters["Mtet/s"] = 1e3 / per_tet(mesh + flow_s);
  state.counters["ns/tet"] = per_tet(mesh + flow_s);
  state.counters["space_mesh"] = per_tet(mesh);
  state.counters["flow"] = per_tet(flow_s);
  state.counters["element"] = per_tet(t.element_pass);
  state.counters["viscosity"] = per_tet(t.viscosity);
  state.counters["geometry"] = per_tet(t.geometry);
  state.counters["normals"] = per_tet(t.normals);
  state.counters["bc"] = per_tet(t.boundary);
  state.counters["update"] = per_tet(t.update + t.mesh_velocity + t.checks);
  state.counters["normal_nodes"] = double(fluid.boundaries().normals_updated());
}

// The slab is one layer thick: h / k gives k^2 times the tetrahedra.
Slab& slab_of(benchmark::State& state) { return slab(1.0 / std::sqrt(double(state.range(0)))); }

void BM_SubStep(benchmark::State& state) {
  Slab& sys = slab_of(state);
  if (!use_simd(state, state.range(2))) return;
  omp_set_num_threads(int(state.range(1)));
  coupling::FlowModel& flow = *sys.s.flow;
  flow.flow()->reset_timings();
  double mesh = 0.0, flow_s = 0.0;
  long substeps = 0;
  bool forward = true;
  // One shell step of the run per iteration, at the default case's sub-step count: the
  // window (between two shell states micrometres apart, swinging back and forth) is as long
  // as kSubSteps sub-steps of the auto rule. Per-window work (the stable-step check, the
  // space mesh's time modes, the flow's snapshot) is so shared as in the run.
  constexpr double kSubSteps = 34.0;
  const double window = kSubSteps * sys.dt_f / 0.9;
  for (auto _ : state) {
    const double t = flow.time();
    if (forward)
      sys.s.motion->set_window(t, window, sys.u0, sys.v0, sys.u1, sys.v1);
    else
      sys.s.motion->set_window(t, window, sys.u1, sys.v1, sys.u0, sys.v0);
    forward = !forward;
    const coupling::FlowStepReport r = flow.advance(*sys.s.motion, t + window);
    substeps += r.substeps;
    mesh += r.mesh_seconds;
    flow_s += r.flow_seconds;
  }
  omp_set_num_threads(omp_get_num_procs());
  state.counters["substeps"] = double(substeps) / double(state.iterations());
  per_tet_counters(state, sys, mesh, flow_s, double(substeps));
}
// Arguments: refinement (1, 4, 16 times the tetrahedra), threads, instruction set.
BENCHMARK(BM_SubStep)
    ->ArgNames({"refine", "threads", "simd"})
    ->ArgsProduct({{1, 4, 16}, {1, 2}, {0, 2, 3}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(1.0);

/// The same flow step on the slab with the mesh at rest (fixed-mesh ALE terms skipped).
void BM_FixedSlabStep(benchmark::State& state) {
  Slab& sys = slab_of(state);
  if (!use_simd(state, state.range(2))) return;
  omp_set_num_threads(int(state.range(1)));
  fluid::FluidModel& fluid = *sys.s.flow->flow();
  fluid.reset_timings();
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) fluid.step(sys.dt_f);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  omp_set_num_threads(omp_get_num_procs());
  per_tet_counters(state, sys, 0.0, seconds);
}
BENCHMARK(BM_FixedSlabStep)
    ->ArgNames({"refine", "threads", "simd"})
    ->ArgsProduct({{1, 16}, {1, 2}, {0, 2, 3}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(1.0);

/// The space-mesh update alone (mover): positions only (velocities = 0, what a run with
/// w = Δx/Δt does) and positions and velocities (mesh_velocity: interpolated).
void BM_SpaceMeshUpdate(benchmark::State& state) {
  Slab& sys = slab_of(state);
  omp_set_num_threads(int(state.range(1)));
  const bool velocities = state.range(2) != 0;
  coupling::FlowModel& flow = *sys.s.flow;
  const auto nn = std::size_t(sys.s.fluid_mesh->num_nodes());
  std::vector<Vec3> x(nn), w(nn);
  const double t = flow.time();
  sys.s.motion->set_window(t, sys.dt_f, sys.u0, sys.v0, sys.u1, sys.v1);
  for (auto _ : state) {
    flow.mover().update(t + 0.5 * sys.dt_f, x, velocities ? std::span<Vec3>(w) : std::span<Vec3>{});
    benchmark::DoNotOptimize(x.data());
  }
  omp_set_num_threads(omp_get_num_procs());
  const double tets = double(sys.s.fluid_mesh->num_cells());
  state.counters["ns/tet"] = benchmark::Counter(double(state.iterations()) * tets / 1e9,
                                                benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_SpaceMeshUpdate)
    ->ArgNames({"refine", "threads", "velocities"})
    ->ArgsProduct({{1, 4, 16}, {1, 2}, {0, 1}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime()
    ->MinTime(0.5);

}  // namespace

BENCHMARK_MAIN();
