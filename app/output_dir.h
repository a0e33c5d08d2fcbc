#pragma once
#include <filesystem>

#include "commands.h"
#include "shellflow/io/case.h"

namespace shellflow::app {
/// The case file of the command line, with its --set overrides applied.
io::Case read_case(const CommonOptions& options);
/// The output directory of a run (-o, else the case's output.directory), created.
std::filesystem::path prepare_output_dir(const io::Case& c, const CommonOptions& options);
}  // namespace shellflow::app
