// Throughput of one full explicit fluid step (artificial viscosity, element pass with the
// Taylor–Galerkin and ALE terms, outflow boundary term, update, boundary conditions,
// positivity check, stable time step) in tetrahedron-updates per second, on structured
// meshes of about 1e4, 1e5 and 1e6 tetrahedra with 1 and 2 threads; and a STREAM-like
// triad that measures the memory bandwidth the step is compared with.
//
//   build/release/bench/fluid/bench_fluid
//   build/release/bench/fluid/bench_fluid --benchmark_filter=Stream
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>
#include <ctime>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "box_mesh.h"
#include "shellflow/core/error.h"
#include "shellflow/fluid/fluid_model.h"
#include "shellflow/fluid/ordering.h"
#include "shellflow/fluid/residual.h"

using namespace shellflow;
using namespace shellflow::fluid;

namespace {

// Compulsory memory traffic of one step, in bytes per tetrahedron, assuming every array is
// streamed once per pass and gathers of node data hit cache (a lower bound). Passes:
// artificial viscosity (nodal p and |u| + c; gradient projection; Laplacian, nu_e and its
// nodal smoothing in one pass; element mean), stable time step, residual element pass,
// outflow faces (neglected), update, boundary conditions (surface, neglected), positivity
// check, density-rate monitor.
double compulsory_bytes_per_tet(double nodes_per_tet) {
  const double conn = 16, grad = 96, scalar = 8;
  const double per_element = (conn + grad + scalar)         // gradient projection: B, V
                             + (conn + grad + 2 * scalar)   // Laplacian + smoothing: B, h, V
                             + (conn + scalar)              // element mean: write nu
                             + (conn + 2 * scalar)          // time step: h, nu
                             + (conn + grad + 2 * scalar);  // residual: B, V, nu
  const double per_node = (40 + 16)                         // state -> p, |u| + c
                          + (24 + 48 + 8 + 48)              // gradient: zero, scatter, read M, scale
                          + (24 + 8 + 8)                    // Laplacian gathers: grad p, |u| + c, p
                          + (8 + 16 + 8 + 16)               // nodal nu: zero, scatter, read M, divide
                          + 8                               // element mean: gather nu_a
                          + (40 + 24 + 32 + 32)             // time step: state, w -> nodal speeds, gather
                          + 2 * 24                          // w of the step: write, test
                          + 40 + (40 + 80)                  // zero r; residual gathers U, scatter r
                          + (40 + 40 + 8 + 40)              // update: U, r, M -> U*
                          + 40                              // positivity check
                          + 2 * 8;                          // density rate: rho^n, rho^{n+1}
  return per_element + nodes_per_tet * per_node;
}

/// Resident set size of this process in bytes (Linux), 0 when unknown.
double resident_bytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmRSS:", 0) == 0) return 1024.0 * std::stod(line.substr(6));
  return 0.0;
}

void FluidStep(benchmark::State& st) {
  const int n = int(st.range(0));
  const int threads = int(st.range(1));
  try {
    set_simd_path(SimdPath(st.range(2)));
  } catch (const shellflow::Error& e) {
    st.SkipWithError(e.what());
    return;
  }
  st.SetLabel(std::string(to_string(simd_path())));
  omp_set_num_threads(threads);
  const double rss_before = resident_bytes();
  auto mesh = bench::box_mesh(n);
  renumber_for_locality(mesh);
  FluidOptions options;
  options.q_dif = 1.0;
  const double gamma = options.gas.gamma;
  const Primitive free_stream{1.0, Vec3(2.0, 0.0, 0.0), 1.0 / gamma};
  FluidModel model(std::move(mesh), options,
                   {{"inflow", BoundaryKind::supersonic_inflow, free_stream, {}},
                    {"outflow", BoundaryKind::supersonic_outflow, {}, {}},
                    {"walls", BoundaryKind::slip_wall, {}, {}},
                    {"symmetry", BoundaryKind::symmetry, {}, {}}});
  model.set_state([&](const Vec3& x) {
    const double pi = std::numbers::pi;
    Primitive s = free_stream;
    s.rho *= 1.0 + 0.2 * std::sin(2 * pi * x.x()) * std::sin(pi * x.y());
    s.pressure *= 1.0 + 0.3 * std::exp(-20 * (x - Vec3(0.5, 0.5, 0.5)).squaredNorm());
    return s;
  });
  model.step(model.stable_dt(0.5));  // touch every work array once
  const double rss_model = resident_bytes() - rss_before;
  const std::clock_t cpu_start = std::clock();
  for (auto _ : st) {
    const double dt = model.stable_dt(0.5);
    model.step(dt);
  }
  // Process CPU time over all threads: per-core throughput that other jobs on a shared
  // machine do not distort (real time does, when threads wait for a core).
  const double cpu_seconds = double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  const double tets = model.mesh().num_cells();
  const double nodes = model.mesh().num_nodes();
  st.counters["tets"] = tets;
  st.counters["colours"] = model.num_colours();
  st.counters["tet_updates_per_s"] = benchmark::Counter(tets * double(st.iterations()), benchmark::Counter::kIsRate);
  st.counters["per_core"] = benchmark::Counter(tets * double(st.iterations()) / threads, benchmark::Counter::kIsRate);
  st.counters["memory_per_tet"] = double(model.memory_bytes()) / tets;  // arrays of the model
  st.counters["rss_per_tet"] = rss_model / tets;                        // RSS growth (0 when memory is reused)
  st.counters["per_core_cpu"] = tets * double(st.iterations()) / cpu_seconds;
  const double bytes = compulsory_bytes_per_tet(nodes / tets);
  st.counters["bytes_per_tet"] = bytes;
  st.counters["bandwidth"] = benchmark::Counter(bytes * tets * double(st.iterations()), benchmark::Counter::kIsRate,
                                                benchmark::Counter::kIs1024);
}
// Arguments: n (12: 10 368 tets, 26: 105 456, 55: 998 250), threads, instruction set of the
// element pass (0 sse2, 1 avx2, 2 avx2-fma, 3 avx512).
BENCHMARK(FluidStep)
    ->ArgNames({"n", "threads", "simd"})
    ->ArgsProduct({{12, 26, 55}, {1, 2}, {0, 2, 3}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// STREAM triad a = b + s c on arrays far larger than the caches; 24 bytes per entry
// (STREAM's convention, write-allocate traffic not counted).
void StreamTriad(benchmark::State& st) {
  const int threads = int(st.range(0));
  omp_set_num_threads(threads);
  const long n = 1L << 24;
  std::vector<double> a(std::size_t(n), 0.0), b(std::size_t(n), 1.0), c(std::size_t(n), 2.0);
  const double s = 3.0;
  for (auto _ : st) {
    double* pa = a.data();
    const double* pb = b.data();
    const double* pc = c.data();
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) pa[i] = pb[i] + s * pc[i];
    benchmark::DoNotOptimize(pa);
    benchmark::ClobberMemory();
  }
  st.counters["bandwidth"] = benchmark::Counter(24.0 * double(n) * double(st.iterations()), benchmark::Counter::kIsRate,
                                                benchmark::Counter::kIs1024);
}
BENCHMARK(StreamTriad)->ArgNames({"threads"})->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
