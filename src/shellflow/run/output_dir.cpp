#include "shellflow/run/output_dir.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <string_view>
#include <vector>

#include "shellflow/core/error.h"
#include "shellflow/core/version.h"
#include "shellflow/io/checkpoint.h"
#include "shellflow/io/plot_runner.h"

namespace shellflow::run {

std::filesystem::path prepare_output_dir(const io::Case& c, const std::optional<std::filesystem::path>& output_dir) {
  const auto dir = output_dir.value_or(c.output.directory);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    throw Error(
        fmt::format("{}: cannot create the output directory ({}); choose another with -o", dir.string(), ec.message()));
  }
  return dir;
}

namespace {

// The fixed names of run output (docs/output.md); the numbered ones are matched below.
constexpr std::array<std::string_view, 17> kRunOutputNames = {
    "fluid.pvd",        "shell.pvd",          "space.pvd",          "modes.pvd",          "shell_modes.vtu",
    "modes.csv",        "modes.json",         "probes.csv",         "probes.png",         "coupling.csv",
    "mesh_quality.csv", "mesh_quality.png",   "motion_quality.csv", "motion_quality.png", "response.json",
    "flutter.png",      "flutter_growth.png",
};

bool all_digits(std::string_view s, std::size_t at_least) {
  return s.size() >= at_least &&
         std::all_of(s.begin(), s.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
}

}  // namespace

bool is_run_output_name(const std::string& full) {
  if (io::is_checkpoint_name(full)) return true;
  std::string_view name = full;
  if (name.ends_with(".tmp")) name.remove_suffix(4);  // a write interrupted by a crash
  if (std::find(kRunOutputNames.begin(), kRunOutputNames.end(), name) != kRunOutputNames.end()) return true;
  if (!name.ends_with(".vtu")) return false;
  name.remove_suffix(4);
  // <mesh>_NNNNNN.vtu (6 digits) and shell_mode_NN.vtu (2 or more).
  for (const std::string_view mesh : io::kMeshKeys) {
    if (name.size() == mesh.size() + 7 && name.starts_with(mesh) && name[mesh.size()] == '_' &&
        all_digits(name.substr(mesh.size() + 1), 6))
      return true;
  }
  constexpr std::string_view mode = "shell_mode_";
  return name.starts_with(mode) && all_digits(name.substr(mode.size()), 2);
}

std::size_t remove_previous_run_output(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::size_t removed = 0;
  std::error_code ec;
  std::vector<fs::path> files;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    // symlink_status: a link named like an output file is not followed, and not removed.
    if (it->symlink_status(ec).type() == fs::file_type::regular && is_run_output_name(it->path().filename().string()))
      files.push_back(it->path());
  }
  if (ec) throw Error(fmt::format("{}: cannot list the output directory ({})", dir.string(), ec.message()));
  for (const fs::path& f : files) {
    if (fs::remove(f, ec)) {
      ++removed;
    } else if (ec) {
      throw Error(
          fmt::format("{}: cannot remove the output of an earlier run ({}); remove it or choose "
                      "another directory with -o",
                      f.string(), ec.message()));
    }
  }
  if (removed > 0)
    spdlog::info(
        "{}: removed {} file(s) of an earlier run (<mesh>_NNNNNN.vtu, <mesh>.pvd, probes.csv, ...); "
        "other files are kept",
        dir.string(), removed);
  return removed;
}

std::vector<std::string> probe_plot_arguments(const io::Case& c, const std::filesystem::path& outdir) {
  std::vector<std::string> args{(outdir / "probes.csv").string(), "-o", (outdir / "probes.png").string()};
  const bool static_run = !c.coupling && !c.motion && c.shell && c.shell->analysis &&
                          c.shell->analysis->type == io::ShellAnalysisType::static_load;
  if (static_run) args.insert(args.end(), {"--x-label", "load factor"});
  for (const io::Probe& p : c.probes) {
    if (!p.reference) continue;
    const auto& r = *p.reference;
    args.insert(args.end(),
                {"--reference", p.name, r.file.string(), r.column, fmt::format("{:.17g}", r.scale), r.label});
  }
  return args;
}

void make_plot(const std::string& script, const std::vector<std::string>& args, bool output_to_stderr) {
  io::PlotRunner runner(SHELLFLOW_PYTHON, output_to_stderr);
  runner.add(script, args);
  runner.run();
}

void make_plots(const PlotJobs& jobs) {
  io::PlotRunner runner(SHELLFLOW_PYTHON);
  for (const PlotJob& job : jobs) runner.add(job.script, job.args);
  runner.run();
}

}  // namespace shellflow::run
