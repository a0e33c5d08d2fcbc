#include "output_dir.h"

#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "shellflow/core/error.h"
#include "shellflow/core/version.h"

namespace shellflow::app {

io::Case read_case(const CommonOptions& options) {
  std::vector<io::KeyOverride> overrides;
  for (const auto& text : options.overrides) overrides.push_back(io::KeyOverride::parse(text));
  return io::read_case(options.case_file, overrides);
}

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

extern "C" char** environ;

void make_plot(const std::string& script, const std::vector<std::string>& args, bool output_to_stderr) {
  const auto path = std::filesystem::path(shellflow::source_dir) / "tools" / script;
  if (!std::filesystem::exists(path)) {
    spdlog::warn("plot skipped: {} not found", path.string());
    return;
  }
  // An argument vector, no shell: output directories may hold any character.
  std::vector<std::string> words{SHELLFLOW_PYTHON, path.string()};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  spdlog::debug("plot: {} {}", SHELLFLOW_PYTHON, fmt::join(std::vector<std::string>(words.begin() + 1, words.end()), " "));
  pid_t pid = 0;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (output_to_stderr) posix_spawn_file_actions_adddup2(&actions, STDERR_FILENO, STDOUT_FILENO);
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    spdlog::warn("plot failed: cannot start {} ({}); the numerical output is complete", SHELLFLOW_PYTHON,
                 std::strerror(rc));
    return;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    spdlog::warn("plot failed ({} exited with status {}); the numerical output is complete", script,
                 WIFEXITED(status) ? WEXITSTATUS(status) : -1);
}

}  // namespace shellflow::app
