#pragma once
// The coloured parallel element loop of ShellModel (for its .cpp files only).
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

}  // namespace shellflow::shell
