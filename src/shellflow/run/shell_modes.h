#pragma once
// The modal analysis of a shell run (shell.analysis.type: modal).
#include <filesystem>

#include "shellflow/io/case.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::run {

/// Natural frequencies and modes about the undeformed shell: modes.csv, modes.json,
/// shell_modes.vtu (every mode as an array) and modes.pvd (one frame per mode).
void write_modes(const io::Case& c, const shell::ShellModel& model, const std::filesystem::path& outdir);

}  // namespace shellflow::run
