#pragma once
// The element loops of ShellModel (for the shell module's .cpp files only): the coloured
// parallel loop and the dispatch on the triangle type.
#include "shellflow/core/parallel.h"
#include "shellflow/fem/reference_element.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::shell {

template <class F>
void ShellModel::for_each_element_parallel(F&& f) const {
  // One colour after the other, its elements shared in chunks among the threads
  // (core/parallel.h). Small meshes run serially: on the 40-element strip handing out the
  // work costs more than the second thread saves.
  constexpr Index min_cells_for_threads = 128;
  constexpr Index grain = 8;  // cubic elements: tens of microseconds each
  const bool threaded = mesh_.num_cells() >= min_cells_for_threads;
  for (const auto& color : colors_) {
    const auto count = static_cast<Index>(color.size());
    parallel::for_range(count, parallel::grain_if(threaded, grain, count), [&](Index begin, Index end) {
      for (Index i = begin; i < end; ++i) f(color[static_cast<std::size_t>(i)]);
    });
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
