// Shape function evaluation as the shell kernel (Tri10 gradients at quadrature points) and
// the space-mesh locator (Tet20 values and gradients at arbitrary points) call it, through
// the element classes and through the runtime facade.
#include <benchmark/benchmark.h>

#include <array>
#include <random>
#include <vector>

#include "shellflow/fem/quadrature.h"
#include "shellflow/fem/reference_element.h"
#include "shellflow/fem/shape_functions.h"

namespace {

using namespace shellflow::fem;

template <class E>
std::vector<std::array<double, E::dim>> points(int n) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0 / E::dim);
  std::vector<std::array<double, E::dim>> x(n);
  for (auto& p : x)
    for (auto& c : p) c = u(rng);
  return x;
}

template <class E>
void BM_Values(benchmark::State& state) {
  const auto x = points<E>(1024);
  double N[E::num_nodes];
  std::size_t i = 0;
  for (auto _ : state) {
    E::eval(x[i++ & 1023].data(), N);
    benchmark::DoNotOptimize(N);
  }
  state.SetItemsProcessed(state.iterations());
}

template <class E>
void BM_Gradients(benchmark::State& state) {
  const auto x = points<E>(1024);
  double dN[E::num_nodes * E::dim];
  std::size_t i = 0;
  for (auto _ : state) {
    E::eval_gradients(x[i++ & 1023].data(), dN);
    benchmark::DoNotOptimize(dN);
  }
  state.SetItemsProcessed(state.iterations());
}

template <class E>
void BM_Hessians(benchmark::State& state) {
  const auto x = points<E>(1024);
  double d2N[E::num_nodes * E::dim * E::dim];
  std::size_t i = 0;
  for (auto _ : state) {
    E::eval_hessians(x[i++ & 1023].data(), d2N);
    benchmark::DoNotOptimize(d2N);
  }
  state.SetItemsProcessed(state.iterations());
}

// The same through the facade's function pointer (an indirect call per evaluation).
template <class E>
void BM_FacadeGradients(benchmark::State& state) {
  const ReferenceElement& re = reference_element(E::gmsh_type);
  const auto x = points<E>(1024);
  double dN[E::num_nodes * E::dim];
  std::size_t i = 0;
  for (auto _ : state) {
    re.eval_gradients(x[i++ & 1023].data(), dN);
    benchmark::DoNotOptimize(dN);
  }
  state.SetItemsProcessed(state.iterations());
}

// Cost of fetching a cached rule (after the first call).
void BM_CachedTriangleRule(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(&triangle_rule(6));
}

BENCHMARK(BM_Values<Tri3>);
BENCHMARK(BM_Values<Tri6>);
BENCHMARK(BM_Values<Tri10>);
BENCHMARK(BM_Gradients<Tri10>);
BENCHMARK(BM_Hessians<Tri10>);
BENCHMARK(BM_Values<Tet4>);
BENCHMARK(BM_Values<Tet10>);
BENCHMARK(BM_Values<Tet20>);
BENCHMARK(BM_Gradients<Tet4>);
BENCHMARK(BM_Gradients<Tet10>);
BENCHMARK(BM_Gradients<Tet20>);
BENCHMARK(BM_FacadeGradients<Tet20>);
BENCHMARK(BM_CachedTriangleRule);

}  // namespace

BENCHMARK_MAIN();
