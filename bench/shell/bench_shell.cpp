// Shell solver timings: one Newton iteration (assembly of F_int and K + factorisation +
// solve) on the 244-node reference strip and on the Sze 3.1 cantilever (8x1 and 16x1
// cubic meshes) and on a 10 000-node Scordelis-Lo panel (panel_33x33.geo); assembly alone
// with 1 and 2 threads (wall time for the panel); LDLT vs LU factorisation; one Newmark
// step of the strip; the whole Sze 3.1 load path.
#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <omp.h>

#include <Eigen/SparseLU>
#include <filesystem>
#include <memory>

#include "shellflow/core/version.h"
#include "shellflow/mesh/gmsh_io.h"
#include "shellflow/shell/newmark_solver.h"
#include "shellflow/shell/static_solver.h"

namespace shellflow::shell {
namespace {

std::unique_ptr<ShellModel> make_model(const std::string& case_file) {
  mesh::MeshingOptions meshing;
  meshing.order = 3;
  ShellSection section;
  if (case_file.starts_with("panel")) {  // Scordelis-Lo data, self weight as gravity
    ShellSection section;
    section.thickness = 0.25;
    section.material = SvkMaterial{4.32e8, 0.0, 1.0};
    auto model = std::make_unique<ShellModel>(
        mesh::generate_mesh(std::filesystem::path(shellflow::source_dir) / "bench/shell" / case_file, meshing, "shell"),
        section);
    model->add_support(Support::symmetry_plane("sym_x", 0));
    model->add_support(Support::symmetry_plane("sym_y", 1));
    Support diaphragm;  // rigid in its plane: y and z fixed
    diaphragm.group = "diaphragm";
    diaphragm.fix_position = {false, true, true};
    model->add_support(diaphragm);
    model->add_gravity(Vec3(0.0, 0.0, -360.0));
    return model;
  }
  const bool strip = case_file.starts_with("strip");
  section.thickness = strip ? 1.35e-3 : 0.1;
  section.material = strip ? SvkMaterial{77.28e9, 0.33, 2710.0} : SvkMaterial{1.2e6, 0.0, 0.0};
  auto model = std::make_unique<ShellModel>(
      mesh::generate_mesh(std::filesystem::path(shellflow::source_dir) / "cases/shell" / case_file, meshing, "shell"),
      section);
  if (strip) {
    model->add_support(Support::clamped("leading_edge"));
    model->add_support(Support::clamped("trailing_edge"));
    model->add_support(Support::symmetry_plane("sides", 2));
    model->add_line_load({"sides", Vec3(0.0, 100.0, 0.0)});
  } else {
    model->add_support(Support::clamped("clamped"));
    model->add_line_load({"tip", Vec3(0.0, 0.0, 4.0)});
  }
  return model;
}

const ShellModel& model_for(int which) {
  static const auto strip = make_model("strip_20x1.geo");
  static const auto sze8 = make_model("sze31_cantilever_8x1.geo");
  static const auto sze16 = make_model("sze31_cantilever_16x1.geo");
  if (which == 3) {  // meshed on first use only (10 000 nodes)
    static const auto panel = make_model("panel_33x33.geo");
    return *panel;
  }
  return which == 0 ? *strip : which == 1 ? *sze8 : *sze16;
}
const char* name_of(int which) {
  return which == 0 ? "strip244" : which == 1 ? "sze31_8x1" : which == 2 ? "sze31_16x1" : "panel10000";
}

/// A deformed state: the first Newton correction at full load (non-trivial stresses).
Eigen::VectorXd deformed_state(const ShellModel& model) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(model.num_dofs()), f;
  SparseMatrix K = model.make_matrix();
  model.assemble(u, f, &K);
  Eigen::VectorXd rhs = model.reference_load() - f;
  NewtonLinearSolver solver;
  solver.solve(K, model.constrained(), rhs);
  return 0.1 * rhs;
}

void BM_NewtonIteration(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(1)));
  const ShellModel& model = model_for(static_cast<int>(state.range(0)));
  state.SetLabel(name_of(static_cast<int>(state.range(0))));
  const Eigen::VectorXd u = deformed_state(model);
  SparseMatrix K = model.make_matrix();
  Eigen::VectorXd f;
  NewtonLinearSolver solver;
  for (auto _ : state) {
    model.assemble(u, f, &K);
    Eigen::VectorXd rhs = model.reference_load() - f;
    solver.solve(K, model.constrained(), rhs);
    benchmark::DoNotOptimize(rhs.data());
  }
  state.counters["nodes"] = model.num_nodes();
  state.counters["dofs"] = model.num_dofs();
}
BENCHMARK(BM_NewtonIteration)->ArgsProduct({{0, 1, 2}, {1, 2}})->Unit(benchmark::kMillisecond);
// The ~10 000-node panel (70 000 dofs): one iteration takes about a minute (factorisation).
BENCHMARK(BM_NewtonIteration)->Args({3, 1})->Iterations(1)->Unit(benchmark::kMillisecond);

void BM_Assembly(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(1)));
  const ShellModel& model = model_for(static_cast<int>(state.range(0)));
  state.SetLabel(name_of(static_cast<int>(state.range(0))));
  const Eigen::VectorXd u = deformed_state(model);
  SparseMatrix K = model.make_matrix();
  Eigen::VectorXd f;
  for (auto _ : state) {
    model.assemble(u, f, &K);
    benchmark::DoNotOptimize(K.valuePtr());
  }
  state.counters["elements/s"] =
      benchmark::Counter(static_cast<double>(model.mesh().num_cells()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Assembly)->ArgsProduct({{0, 1}, {1, 2}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Assembly)->ArgsProduct({{3}, {1, 2}})->Iterations(3)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The internal force alone (no tangent): the cost of a modified-Newton iteration's
/// residual.
void BM_InternalForce(benchmark::State& state) {
  omp_set_num_threads(1);
  const ShellModel& model = model_for(static_cast<int>(state.range(0)));
  state.SetLabel(name_of(static_cast<int>(state.range(0))));
  const Eigen::VectorXd u = deformed_state(model);
  Eigen::VectorXd f;
  for (auto _ : state) {
    model.assemble(u, f, nullptr);
    benchmark::DoNotOptimize(f.data());
  }
}
BENCHMARK(BM_InternalForce)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

/// The pieces of a modified-Newton iteration on the strip besides the internal force: one
/// solve with a kept factorisation (Arg 0) and one product with the mass matrix (Arg 1).
void BM_SolveAndMassProduct(benchmark::State& state) {
  omp_set_num_threads(1);
  const ShellModel& model = model_for(0);
  SparseMatrix K = model.make_matrix(), M = model.make_matrix();
  Eigen::VectorXd f;
  model.assemble(deformed_state(model), f, &K);
  model.assemble_mass(M);
  NewtonLinearSolver solver;
  solver.factorize(K, model.constrained());
  const Eigen::VectorXd rhs = model.reference_load() - f;
  state.SetLabel(state.range(0) == 0 ? "solve strip244" : "M v strip244");
  for (auto _ : state) {
    Eigen::VectorXd x = rhs;
    if (state.range(0) == 0)
      solver.solve(x);
    else
      x = M * rhs;
    benchmark::DoNotOptimize(x.data());
  }
}
BENCHMARK(BM_SolveAndMassProduct)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

/// The strip with a follower pressure of 1 kPa on the whole shell.
ShellModel make_model_copy_with_pressure() {
  ShellModel model = *make_model("strip_20x1.geo");
  model.add_follower_pressure({"", 1000.0});
  return model;
}

/// Factorisation + solve alone on the strip: Eigen SimplicialLDLT with AMD on the full
/// matrix (the previous NewtonLinearSolver), SparseLU, and NewtonLinearSolver (reduced
/// system, node-graph AMD, value map; includes eliminating the supports and the copies),
/// symmetric (Arg 2) and with a follower pressure's load stiffness (Arg 3, reduced LU).
void BM_Factorisation(benchmark::State& state) {
  const ShellModel& model = model_for(0);
  const bool lu = state.range(0) == 1;
  if (state.range(0) >= 2) {  // 3: with the load stiffness of a follower pressure, LU path
    const bool pressure = state.range(0) == 3;
    state.SetLabel(pressure ? "NewtonLinearSolver non-symmetric (reduced SparseLU) strip244"
                            : "NewtonLinearSolver strip244");
    const Eigen::VectorXd u = deformed_state(model);
    SparseMatrix K = model.make_matrix();
    Eigen::VectorXd f;
    model.assemble(u, f, &K);
    const Eigen::VectorXd rhs = model.reference_load() - f;
    if (pressure) {
      ShellModel loaded = make_model_copy_with_pressure();
      Eigen::VectorXd dummy = Eigen::VectorXd::Zero(model.num_dofs());
      loaded.add_follower_loads(u, 1.0, 0.0, dummy, &K);
    }
    NewtonLinearSolver solver;
    for (auto _ : state) {
      Eigen::VectorXd x = rhs;
      solver.solve(K, model.constrained(), x, !pressure);
      benchmark::DoNotOptimize(x.data());
    }
    return;
  }
  state.SetLabel(lu ? "SparseLU strip244" : "SimplicialLDLT strip244");
  const Eigen::VectorXd u = deformed_state(model);
  SparseMatrix K = model.make_matrix();
  Eigen::VectorXd f;
  model.assemble(u, f, &K);
  Eigen::VectorXd rhs = model.reference_load() - f;
  NewtonLinearSolver prepare;
  Eigen::VectorXd tmp = rhs;
  prepare.solve(K, model.constrained(), tmp);  // applies the supports to K
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt;
  Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>> sparse_lu;
  if (lu)
    sparse_lu.analyzePattern(K);
  else
    ldlt.analyzePattern(K);
  for (auto _ : state) {
    Eigen::VectorXd x;
    if (lu) {
      sparse_lu.factorize(K);
      x = sparse_lu.solve(rhs);
    } else {
      ldlt.factorize(K);
      x = ldlt.solve(rhs);
    }
    benchmark::DoNotOptimize(x.data());
  }
}
BENCHMARK(BM_Factorisation)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond);

/// One Newmark step of the reference strip (Newton to the §8 tolerances), free vibration
/// from a uniform initial transverse velocity, Δt = 1e-4 s (~T1/320). Arg: 0 full Newton,
/// 1-3 modified Newton (NewtonOptions::modified) with refresh ratios 0.5, 0.7, 0.9.
void BM_NewmarkStepStrip(benchmark::State& state) {
  omp_set_num_threads(1);
  const ShellModel& model = model_for(0);
  static const char* const labels[] = {"full Newton", "modified Newton, refresh ratio 0.5 (default)",
                                       "modified Newton, refresh ratio 0.7", "modified Newton, refresh ratio 0.9"};
  state.SetLabel(labels[state.range(0)]);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(model.num_dofs());
  for (Index n = 0; n < model.num_nodes(); ++n)
    if (!model.constrained()[static_cast<std::size_t>(7 * n + 1)]) v(7 * n + 1) = 0.1;
  NewmarkOptions options;
  options.newton.modified = state.range(0) >= 1;
  if (state.range(0) == 2) options.newton.refresh_ratio = 0.7;
  if (state.range(0) == 3) options.newton.refresh_ratio = 0.9;
  NewmarkSolver solver(model, options);
  solver.set_initial_state(Eigen::VectorXd::Zero(model.num_dofs()), v);
  int iterations = 0, steps = 0;
  const int factorizations_before = solver.matrix_factorizations();
  for (auto _ : state) {
    iterations += solver.advance(1e-4);
    ++steps;
  }
  state.counters["newton_its_per_step"] = static_cast<double>(iterations) / std::max(1, steps);
  state.counters["factorizations_per_step"] =
      static_cast<double>(solver.matrix_factorizations() - factorizations_before) / std::max(1, steps);
}
BENCHMARK(BM_NewmarkStepStrip)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond);

/// One Newmark step of the reference strip under a follower pressure of 1 kPa on the whole
/// strip (non-symmetric tangent), from rest, Δt = 1e-4 s. Arg: 0 full Newton, 1 modified
/// Newton (refresh ratio 0.5).
void BM_NewmarkStepStripPressure(benchmark::State& state) {
  omp_set_num_threads(1);
  static const auto model = [] {
    auto m = make_model("strip_20x1.geo");
    m->add_follower_pressure({"", 1000.0});
    return m;
  }();
  state.SetLabel(state.range(0) == 0 ? "follower pressure, full Newton" : "follower pressure, modified Newton");
  NewmarkOptions options;
  options.newton.modified = state.range(0) == 1;
  NewmarkSolver solver(*model, options, [](double) { return 1.0; });
  solver.set_initial_state(Eigen::VectorXd::Zero(model->num_dofs()), Eigen::VectorXd::Zero(model->num_dofs()));
  int iterations = 0, steps = 0;
  const int factorizations_before = solver.matrix_factorizations();
  for (auto _ : state) {
    iterations += solver.advance(1e-4);
    ++steps;
  }
  state.counters["newton_its_per_step"] = static_cast<double>(iterations) / std::max(1, steps);
  state.counters["factorizations_per_step"] =
      static_cast<double>(solver.matrix_factorizations() - factorizations_before) / std::max(1, steps);
}
BENCHMARK(BM_NewmarkStepStripPressure)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

/// The whole Sze 3.1 static run on the 8x1 cubic mesh (20 load steps to P_max = 4, Newton
/// to the §8 tolerances), one thread, meshing excluded (the target: <= 0.2 s).
void BM_Sze31FullRun(benchmark::State& state) {
  omp_set_num_threads(1);
  const ShellModel& model = model_for(1);
  int iterations = 0, runs = 0;
  NewtonOptions options;
  options.modified = state.range(0) >= 1;
  if (state.range(0) == 2) options.refresh_ratio = 0.25;
  if (state.range(0) == 3) options.refresh_ratio = 0.8;
  state.SetLabel(options.modified ? fmt::format("modified Newton, refresh ratio {}", options.refresh_ratio)
                                  : std::string("full Newton"));
  for (auto _ : state) {
    StaticSolver solver(model, options);
    for (const LoadStep& s : solver.run(20, 1.0)) iterations += s.iterations;
    ++runs;
    benchmark::DoNotOptimize(solver.displacement().data());
  }
  state.counters["newton_its"] = static_cast<double>(iterations) / std::max(1, runs);
}
BENCHMARK(BM_Sze31FullRun)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace shellflow::shell

BENCHMARK_MAIN();
