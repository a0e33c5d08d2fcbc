#pragma once
// The modal analysis of a shell run (shell.analysis.type: modal).
#include <filesystem>
#include <vector>

#include "shellflow/io/case.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::run {

/// Natural frequencies and modes about the undeformed shell: modes.csv, modes.json,
/// shell_modes.vtu (every mode as an array) and modes.pvd (one frame per mode).
void write_modes(const io::Case& c, const shell::ShellModel& model, const std::filesystem::path& outdir);

/// The nodal displacement part (x, y, z per node) of a mode vector in the shell's dofs,
/// scaled to a largest nodal |dx| of 1 with its largest component positive.
std::vector<double> normalised_mode_displacement(const Eigen::VectorXd& phi, Index nodes);

}  // namespace shellflow::run
