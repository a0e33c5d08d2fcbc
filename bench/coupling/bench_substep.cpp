// One fluid sub-step of the coupled flutter run, part by part, on the default panel slab
// (clamped_clamped.yaml: 8 622 nodes / 25 074 tetrahedra) and on its 4x and 16x refinements
// (meshes.fluid.size_factor 0.5 and 0.25), with 1 and 2 threads:
//   space-mesh update   the space mesh moved by IDW of the shell motion, every fluid node
//                       interpolated (positions and velocities), the wall velocities of the
//                       slip condition (FlowModel's mesh_seconds);
//   flow step           one explicit step on the moved mesh (FlowModel's flow_seconds), and
//                       inside it (fluid::StepTimings): mesh velocity, artificial viscosity,
//                       element pass, update, geometry, normals, boundary conditions, checks.
// Every part as ns per tetrahedron; the whole sub-step as M tet-updates/s.
//
//   build/release/bench/coupling/bench_substep [--benchmark_repetitions=5 --benchmark_report_aggregates_only=true]
//
// The fixed-mesh step of the cube benchmark (bench/fluid/bench_fluid, FluidStep) runs in the
// same way; run both in one session to compare them.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>
#include <map>
#include <memory>

#include "shellflow/core/version.h"
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
                        std::vector<io::KeyOverride>{io::KeyOverride::parse(
                            fmt::format("meshes.fluid.size_factor={}", size_factor))})),
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

void BM_SubStep(benchmark::State& state) {
  // The slab is one layer thick: h / k gives k^2 times the tetrahedra.
  const double size_factor = 1.0 / std::sqrt(double(state.range(0)));
  const int threads = int(state.range(1));
  Slab& sys = slab(size_factor);
  omp_set_num_threads(threads);
  coupling::FlowModel& flow = *sys.s.flow;
  fluid::FluidModel& fluid = *flow.flow();
  fluid.reset_timings();
  double mesh = 0.0, flow_s = 0.0;
  bool forward = true;
  for (auto _ : state) {
    // One sub-step: the window swings between the two shell states (micrometres).
    const double t = flow.time();
    if (forward)
      sys.s.motion->set_window(t, sys.dt_f, sys.u0, sys.v0, sys.u1, sys.v1);
    else
      sys.s.motion->set_window(t, sys.dt_f, sys.u1, sys.v1, sys.u0, sys.v0);
    forward = !forward;
    const coupling::FlowStepReport r = flow.advance(*sys.s.motion, t + sys.dt_f);
    if (r.substeps != 1) state.SkipWithError("more than one sub-step");
    mesh += r.mesh_seconds;
    flow_s += r.flow_seconds;
  }
  omp_set_num_threads(omp_get_num_procs());
  const double n = double(state.iterations()), tets = double(sys.s.fluid_mesh->num_cells());
  const auto per_tet = [&](double seconds) { return 1e9 * seconds / (n * tets); };
  const fluid::StepTimings& t = fluid.timings();
  state.counters["tets"] = tets;
  state.counters["Mtet/s"] = benchmark::Counter(tets * n / 1e6, benchmark::Counter::kIsRate);
  state.counters["ns/tet"] = per_tet(mesh + flow_s);
  state.counters["space_mesh"] = per_tet(mesh);
  state.counters["flow"] = per_tet(flow_s);
  state.counters["element"] = per_tet(t.element_pass);
  state.counters["viscosity"] = per_tet(t.viscosity);
  state.counters["geometry"] = per_tet(t.geometry);
  state.counters["normals"] = per_tet(t.normals);
  state.counters["bc"] = per_tet(t.boundary);
  state.counters["update"] = per_tet(t.update + t.mesh_velocity + t.checks);
}
// Arguments: refinement (1, 4, 16 times the tetrahedra), threads.
BENCHMARK(BM_SubStep)
    ->ArgNames({"refine", "threads"})
    ->ArgsProduct({{1, 4, 16}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(1.0);

}  // namespace

BENCHMARK_MAIN();
