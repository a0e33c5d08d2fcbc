#include "output_dir.h"

#include <spdlog/spdlog.h>

#include <cstdlib>

#include "shellflow/core/error.h"
#include "shellflow/core/version.h"

namespace shellflow::app {

std::filesystem::path prepare_output_dir(const io::Case& c, const CommonOptions& options) {
  const auto dir = options.output_dir.value_or(c.output.directory);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    throw Error(fmt::format("{}: cannot create the output directory ({}); choose another with -o",
                            dir.string(), ec.message()));
  }
  return dir;
}

void make_plot(const std::string& script, const std::string& args) {
  const auto path = std::filesystem::path(shellflow::source_dir) / "tools" / script;
  if (!std::filesystem::exists(path)) {
    spdlog::warn("plot skipped: {} not found", path.string());
    return;
  }
  const std::string command = fmt::format("\"{}\" \"{}\" {}", SHELLFLOW_PYTHON, path.string(), args);
  spdlog::debug("plot: {}", command);
  if (std::system(command.c_str()) != 0) {
    spdlog::warn("plot failed ({}); the numerical output is complete", command);
  }
}

}  // namespace shellflow::app
