#pragma once
// The element loops of ShellModel (for the shell module's .cpp files only): the coloured
// parallel loop and the dispatch on the triangle type.
#include "shellflow/fem/reference_element.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::shell {

template <class F>
void ShellModel::for_each_element_parallel(F&& f) const {
  // One parallel region for all colours (the implicit barrier of `omp for` separates them).
  // Small meshes run serially: on the 40-element strip the fork/join and the barriers cost
  // more than the second thread saves (measured: 2 threads 3-10x slower on the loaded machine).
  constexpr Index min_cells_for_threads = 128;
  const bool threaded = mesh_.num_cells() >= min_cells_for_threads;
#pragma omp parallel if (threaded)
  for (const auto& color : colors_) {
    const auto count = static_cast<std::ptrdiff_t>(color.size());
#pragma omp for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) f(color[static_cast<std::size_t>(i)]);
  }
}

/// Calls f(element) with the reference triangle type of the model's mesh (3, 6 or 10 nodes).
template <class F>
void visit_triangle(const ShellModel& model, F&& f) {
  fem::visit_element_type(static_cast<int>(model.mesh().cells.type), [&](auto element) {
    using E = decltype(element);
    if constexpr (E::dim == 2) f(element);
  });
}

}  // namespace shellflow::shell
