#include "shellflow/run/output_dir.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdlib>
#include <string_view>
#include <vector>

#include "shellflow/core/error.h"
#include "shellflow/core/output_file.h"
#include "shellflow/core/version.h"
#include "shellflow/io/checkpoint.h"
#include "shellflow/io/plot_runner.h"

namespace shellflow::run {

namespace {

// The fixed names of run output (docs/output.md); the numbered ones are matched below.
constexpr std::array<std::string_view, 19> kRunOutputNames = {
    "fluid.pvd",        "shell.pvd",          "space.pvd",          "modes.pvd",          "shell_modes.vtu",
    "modes.csv",        "modes.json",         "probes.csv",         "probes.png",         "coupling.csv",
    "mesh_quality.csv", "mesh_quality.png",   "motion_quality.csv", "motion_quality.png", "response.json",
    "flutter.png",      "flutter_growth.png", "deflection.png",     "modes.png",
};

bool all_digits(std::string_view s, std::size_t at_least) {
  return s.size() >= at_least &&
         std::all_of(s.begin(), s.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
}

/// Whether a link named `name` in an output folder could be written through: the names of
/// every file shellflow writes there, by their endings.
bool is_output_like_name(std::string_view name) {
  constexpr std::array<std::string_view, 13> kEndings = {".vtu",   ".pvtu", ".pvd", ".csv", ".json", ".png", ".msh",
                                                         ".cache", ".ckpt", ".tmp", ".log", ".txt",  ".lock"};
  return name == "points" ||
         std::any_of(kEndings.begin(), kEndings.end(), [&](std::string_view e) { return name.ends_with(e); });
}

/// The files of `mesh`, `flutter` and `study` (and meshes of every run).
bool is_command_output_name(std::string_view name) {
  constexpr std::array<std::string_view, 9> kNames = {"meshes.json",       "flutter.json",      "flutter_locus.csv",
                                                      "flutter_locus.png", "flutter_modes.png", "study.csv",
                                                      "study.json",        "study_growth.png",  "study_lco.png"};
  return std::find(kNames.begin(), kNames.end(), name) != kNames.end() || name.ends_with(".vtu") ||
         name.ends_with(".msh") || name.ends_with(".msh.cache");
}

/// The root folder and the home folder are never a run's output folder.
void refuse_system_folder(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(fs::absolute(dir, ec), ec);
  if (ec) return;
  std::string what;
  if (canonical == canonical.root_path()) {
    what = "the root folder";
  } else if (const char* home = std::getenv("HOME"); home && *home && fs::weakly_canonical(home, ec) == canonical) {
    what = "your home folder";
  }
  if (!what.empty())
    throw Error(
        fmt::format("{}: is {}; a run writes many files and removes those of an earlier run in its output "
                    "folder: give a folder of its own with -o (e.g. -o {})",
                    printable(dir.string()), what, printable((dir / "shellflow-out").string())));
}

}  // namespace

OutputFolder open_output_dir(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  refuse_system_folder(dir);
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->symlink_status(ec).type() == fs::file_type::symlink && is_output_like_name(it->path().filename().string()))
      throw Error(link_refusal(it->path()));
  }
  if (ec) throw Error(fmt::format("{}: cannot list the output directory ({})", printable(dir.string()), ec.message()));
  return {dir, OutputLock(dir)};
}

OutputFolder prepare_output_dir(const io::Case& c, const std::optional<std::filesystem::path>& output_dir) {
  namespace fs = std::filesystem;
  const auto dir = output_dir.value_or(c.output.directory);
  refuse_system_folder(dir);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    throw Error(fmt::format("{}: cannot create the output directory ({}); choose another with -o",
                            printable(dir.string()), ec.message()));
  }
  // A folder shellflow never wrote in (no lock file) keeps its files: none of them is replaced
  // or removed as "an earlier run's output".
  if (!fs::exists(fs::symlink_status(dir / OutputLock::kFileName, ec))) {
    std::vector<std::string> foreign;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if (is_run_output_name(name) || is_command_output_name(name)) foreign.push_back(name);
    }
    if (!foreign.empty())
      throw Error(fmt::format(
          "{}: holds {}{} but is not a shellflow output folder (no {}); a run would replace them: choose a new "
          "folder with -o, or move them away",
          printable(dir.string()), printable(foreign.front()),
          foreign.size() > 1 ? fmt::format(" and {} other file(s) named like a run's output", foreign.size() - 1) : "",
          OutputLock::kFileName));
  }
  return open_output_dir(dir);
}

std::optional<FrameFile> frame_file(std::string_view name) {
  const bool parallel = name.ends_with(".pvtu");
  if (!parallel && !name.ends_with(".vtu")) return std::nullopt;
  name.remove_suffix(parallel ? 5 : 4);
  for (const std::string_view mesh : io::kMeshKeys) {
    if (name.size() < mesh.size() + 7 || !name.starts_with(mesh) || name[mesh.size()] != '_') continue;
    const std::string_view digits = name.substr(mesh.size() + 1, 6);
    const std::string_view rest = name.substr(mesh.size() + 7);  // "" or (a piece) "_p<rank>"
    const bool piece = !parallel && rest.size() > 2 && rest.starts_with("_p") && all_digits(rest.substr(2), 1);
    if (!all_digits(digits, 6) || (!rest.empty() && !piece)) continue;
    const std::string frame = std::string(name.substr(0, mesh.size() + 7));
    return FrameFile{std::stol(std::string(digits)), frame + (parallel || piece ? ".pvtu" : ".vtu")};
  }
  return std::nullopt;
}

bool is_run_output_name(const std::string& full) {
  if (io::is_checkpoint_name(full)) return true;
  std::string_view name = full;
  if (name.ends_with(".tmp")) name.remove_suffix(4);  // a write interrupted by a crash
  if (std::find(kRunOutputNames.begin(), kRunOutputNames.end(), name) != kRunOutputNames.end()) return true;
  if (frame_file(name)) return true;
  if (!name.ends_with(".vtu")) return false;
  name.remove_suffix(4);
  // shell_mode_NN.vtu (2 or more digits).
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

std::vector<std::string> shell_field_plot_arguments(const mesh::Mesh& shell, const std::filesystem::path& outdir,
                                                    bool time_series) {
  if (shell.nodes.empty()) return {};
  Vec3 lo = shell.nodes.front(), hi = lo;
  for (const Vec3& x : shell.nodes) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  Vec3 extent = hi - lo;
  std::sort(extent.data(), extent.data() + 3);
  if (extent(1) < 0.2 * extent(2)) return {};
  if (time_series) return {(outdir / "shell.pvd").string(), "-o", (outdir / "deflection.png").string()};
  return {(outdir / "shell_modes.vtu").string(), "--modes", "--frequencies",
          (outdir / "modes.csv").string(),       "-o",      (outdir / "modes.png").string()};
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
