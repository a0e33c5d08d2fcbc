#pragma once
// Case file -> shell model: the builders every kind of run shares (shell alone, coupled).
#include "shellflow/io/case.h"
#include "shellflow/mesh/mesh.h"
#include "shellflow/shell/newmark_solver.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::setup {

/// The shell model of a case's shell section on its mesh: section, supports, loads. Errors
/// carry the case file's line.
shell::ShellModel build_shell_model(const io::ShellSection& s, const mesh::Mesh& mesh);

/// Newmark options of a dynamic shell analysis.
shell::NewmarkOptions newmark_options(const io::ShellAnalysis& analysis);

}  // namespace shellflow::setup
