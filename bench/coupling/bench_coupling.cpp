// Coupled panel flutter, piece by piece, on the cases' own meshes (cases/panel_flutter):
//   BM_ShellStepPiston       one staggered shell step with piston-theory loads (the whole
//                            piston run is 1400 of them);
//   BM_SpaceMeshUpdate       the fluid-mesh motion of one fluid sub-step (space mesh IDW +
//                            interpolation to every fluid node + wall velocity), paper meshes;
//   BM_FlowStepMoving        one explicit flow step on the moved mesh, paper meshes;
//   BM_CoupledShellStepEuler one whole shell step of the Euler-coupled run (shell + n_sub
//                            sub-steps + loads), paper meshes;
//   BM_CheckpointSave/Write/ReadAndRestore  a checkpoint of the Euler-coupled state, paper
//                            meshes: into the archive, to disk (fsync), back;
//   BM_FlutterBasis          the linear flutter analysis' modal basis (24 in-vacuo modes +
//                            projected piston-theory matrices) of the reference strip;
//   BM_FlutterSweep50        its sweep of 50 lambda values + the bisection of the boundary;
//   BM_LoadTransfer/0|1      one exchange of the loads, pressure only / pressure and shear
//                            (clamped-sliding panel, inviscid / viscous, paper meshes);
//   BM_FlowSubstep/0|1       one fluid sub-step of those runs, Euler / Navier-Stokes.
// Median of repetitions: --benchmark_repetitions=5 --benchmark_report_aggregates_only=true.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include "shellflow/core/archive.h"
#include "shellflow/core/version.h"
#include "shellflow/coupling/linear_flutter.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/io/checkpoint.h"
#include "shellflow/setup/coupled_setup.h"

namespace {

using namespace shellflow;

const std::filesystem::path cases = std::filesystem::path(source_dir) / "cases" / "panel_flutter";

struct System {
  io::Case c;
  io::CaseMeshes meshes;
  setup::CoupledSystem s;
  explicit System(io::Case from)
      : c(std::move(from)), meshes(io::load_case_meshes(c, std::nullopt)), s(setup::build_coupled_system(c, meshes)) {
    for (int i = 0; i < 50; ++i) s.driver->step(c.time->step);
  }
  explicit System(const char* file, const char* folder = "panel_flutter")
      : c(io::read_case(cases.parent_path() / folder / file)),
        meshes(io::load_case_meshes(c, std::nullopt)),
        s(setup::build_coupled_system(c, meshes)) {
    // Past the start-up, with the panel moving.
    for (int i = 0; i < 50; ++i) s.driver->step(c.time->step);
  }
};

void BM_ShellStepPiston(benchmark::State& state) {
  System sys("clamped_sliding_piston.yaml");
  for (auto _ : state) sys.s.driver->step(sys.c.time->step);
  state.counters["shell_nodes"] = double(sys.s.shell->num_nodes());
}
BENCHMARK(BM_ShellStepPiston)->Unit(benchmark::kMillisecond);

System& euler() {
  static System sys("clamped_clamped.yaml");
  return sys;
}

void BM_SpaceMeshUpdate(benchmark::State& state) {
  System& sys = euler();
  auto& mover = const_cast<motion::FluidMeshMover&>(sys.s.flow->mover());
  std::vector<Vec3> x(sys.s.fluid_mesh->nodes.size()), w(x.size());
  const double t = sys.s.solver->time() - 0.5 * sys.c.time->step;  // inside the last window
  for (auto _ : state) {
    mover.update(t, x, w);
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["fluid_nodes"] = double(x.size());
}
BENCHMARK(BM_SpaceMeshUpdate)->Unit(benchmark::kMicrosecond);

/// One flow step of `sys` on a moving mesh (w != 0), from the same state every time.
void time_flow_step(benchmark::State& state, System& sys) {
  fluid::FluidModel& flow = *sys.s.flow->flow();
  const fluid::FluidSnapshot start = flow.snapshot();
  const double dt = 0.5 * flow.stable_dt(0.5);
  std::vector<Vec3> x(flow.positions().begin(), flow.positions().end());
  for (auto& p : x) p.y() += 1e-9 * p.x();
  for (auto _ : state) {
    state.PauseTiming();
    flow.restore(start);
    state.ResumeTiming();
    flow.step(dt, x);
  }
  flow.restore(start);
  state.counters["tets"] = double(sys.s.fluid_mesh->num_cells());
  state.counters["Mtet/s"] = benchmark::Counter(
      double(sys.s.fluid_mesh->num_cells()) * double(state.iterations()) / 1e6, benchmark::Counter::kIsRate);
}

void BM_FlowStepMoving(benchmark::State& state) { time_flow_step(state, euler()); }
BENCHMARK(BM_FlowStepMoving)->Unit(benchmark::kMillisecond);

void BM_CoupledShellStepEuler(benchmark::State& state) {
  System& sys = euler();
  int substeps = 0;
  for (auto _ : state) substeps = sys.s.driver->step(sys.c.time->step).flow.substeps;
  state.counters["substeps"] = substeps;
}
BENCHMARK(BM_CoupledShellStepEuler)->Unit(benchmark::kMillisecond);

// The clamped-sliding panel in the same stream, inviscid (slip walls, pressure only) and
// viscous (no-slip walls: pressure and shear), paper meshes, q_dif 1.0 for both as in
// bench/coupling/viscous_flutter.py.
System& sliding(bool viscous) {
  static System inviscid = [] {
    io::Case c = io::read_case(cases / "clamped_sliding.yaml");
    c.fluid->analysis->q_dif = 1.0;
    c.fluid->analysis->cfl = 0.5;
    return System(std::move(c));
  }();
  static System with_shear("flutter_viscous.yaml", "viscous_coupling");
  return viscous ? with_shear : inviscid;
}

// One exchange of the loads: the pressure rise at the shell's load points, and with a no-slip
// wet wall the shear (the viscous residual's reaction at the wet nodes, interpolated).
void BM_LoadTransfer(benchmark::State& state) {
  System& sys = sliding(state.range(0) != 0);
  const std::size_t n = sys.s.shell->load_points().size();
  std::vector<double> dp(n);
  std::vector<Vec3> shear(n);
  for (auto _ : state) {
    sys.s.aerodynamics->pressure_rise(sys.s.solver->displacement(), sys.s.solver->velocity(), dp);
    if (sys.s.aerodynamics->has_shear()) sys.s.aerodynamics->shear(shear);
    benchmark::DoNotOptimize(dp.data());
    benchmark::DoNotOptimize(shear.data());
  }
  state.counters["load_points"] = double(n);
}
BENCHMARK(BM_LoadTransfer)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// One fluid sub-step of the coupled run on the moved mesh: Euler against Navier-Stokes.
void BM_FlowSubstep(benchmark::State& state) { time_flow_step(state, sliding(state.range(0) != 0)); }
BENCHMARK(BM_FlowSubstep)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// A checkpoint of the default flutter case (docs/restart.md): the coupled state into the
// archive, the file written (tmp + fsync + rename), read and verified, and restored.
void BM_CheckpointSave(benchmark::State& state) {
  System& sys = euler();
  std::size_t bytes = 0;
  for (auto _ : state) {
    ArchiveWriter out;
    sys.s.driver->save(out);
    bytes = out.bytes().size();
    benchmark::DoNotOptimize(out.bytes().data());
  }
  state.counters["MB"] = double(bytes) / 1e6;
}
BENCHMARK(BM_CheckpointSave)->Unit(benchmark::kMillisecond);

/// A scratch folder (made again by every benchmark, removed at its end).
std::filesystem::path checkpoint_dir() {
  const auto dir = std::filesystem::temp_directory_path() / ("shellflow-bench-ckpt-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

void BM_CheckpointWrite(benchmark::State& state) {
  System& sys = euler();
  ArchiveWriter out;
  sys.s.driver->save(out);
  io::CheckpointHeader header;
  header.case_name = sys.c.name;
  long step = 0;
  for (auto _ : state) {
    header.step = ++step;
    io::write_checkpoint(checkpoint_dir(), header, out.bytes());
  }
  state.counters["MB"] = double(out.bytes().size()) / 1e6;
  std::filesystem::remove_all(checkpoint_dir());
}
BENCHMARK(BM_CheckpointWrite)->Unit(benchmark::kMillisecond);

void BM_CheckpointReadAndRestore(benchmark::State& state) {
  System& sys = euler();
  ArchiveWriter out;
  sys.s.driver->save(out);
  io::CheckpointHeader header;
  header.step = 999999;
  io::write_checkpoint(checkpoint_dir(), header, out.bytes());
  for (auto _ : state) {
    const io::Checkpoint c = io::read_checkpoint(io::checkpoint_path(checkpoint_dir(), 999999));
    ArchiveReader in(c.payload, "bench");
    sys.s.driver->restore(in);
  }
  std::filesystem::remove_all(checkpoint_dir());
}
BENCHMARK(BM_CheckpointReadAndRestore)->Unit(benchmark::kMillisecond);

}  // namespace

void BM_FlutterBasis(benchmark::State& state) {
  System sys("clamped_clamped_piston.yaml");
  for (auto _ : state) {
    coupling::LinearFlutterSystem f(*sys.s.shell, 24);
    benchmark::DoNotOptimize(f);
  }
}
BENCHMARK(BM_FlutterBasis)->Unit(benchmark::kMillisecond);

void BM_FlutterSweep50(benchmark::State& state) {
  System sys("clamped_clamped_piston.yaml");
  const coupling::LinearFlutterSystem f(*sys.s.shell, 24);
  const coupling::PistonAerodynamics aero(f, sys.s.piston->theory());
  const auto st = setup::flutter_setting(sys.c, *sys.s.shell);
  int bisections = 0;
  for (auto _ : state) {
    const auto r = coupling::sweep_flutter(f, aero, st, coupling::FlutterParameter::lambda, 0.0, 1000.0, 50);
    bisections = r.critical ? r.critical->bisections : -1;
  }
  state.counters["bisections"] = bisections;
}
BENCHMARK(BM_FlutterSweep50)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
