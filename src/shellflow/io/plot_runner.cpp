#include "shellflow/io/plot_runner.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spawn.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "shellflow/core/version.h"

extern "C" char** environ;

namespace shellflow::io {

PlotRunner::PlotRunner(std::filesystem::path python, bool output_to_stderr)
    : python_(std::move(python)), output_to_stderr_(output_to_stderr) {}

std::filesystem::path PlotRunner::tools_dir() { return std::filesystem::path(shellflow::source_dir) / "tools"; }

void PlotRunner::add(const std::string& script, std::vector<std::string> args) {
  const auto path = tools_dir() / script;
  if (!std::filesystem::exists(path)) {
    spdlog::warn("plot skipped: {} not found", path.string());
    return;
  }
  jobs_.push_back({script, std::move(args)});
}

bool PlotRunner::run() {
  if (jobs_.empty()) return true;
  std::vector<std::string> scripts;
  for (const auto& job : jobs_) scripts.push_back(job.script);
  const std::string names = fmt::format("{}", fmt::join(scripts, ", "));
  const auto runner = tools_dir() / "plot_run.py";
  if (!std::filesystem::exists(runner)) {
    spdlog::warn("plot skipped ({}): {} not found", names, runner.string());
    jobs_.clear();
    return false;
  }
  // An argument vector, no shell: output directories may hold any character. Each job is
  // --job SCRIPT N ARG1..ARGN, so an argument may be any string.
  std::vector<std::string> words{python_.string(), runner.string()};
  for (auto& job : jobs_) {
    words.insert(words.end(), {"--job", job.script, std::to_string(job.args.size())});
    words.insert(words.end(), std::make_move_iterator(job.args.begin()), std::make_move_iterator(job.args.end()));
  }
  jobs_.clear();
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  spdlog::debug("plot: {}", fmt::join(words, " "));

  pid_t pid = 0;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (output_to_stderr_) posix_spawn_file_actions_adddup2(&actions, STDERR_FILENO, STDOUT_FILENO);
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    spdlog::warn("plot failed ({}): cannot start {} ({}); the numerical output is complete", names, python_.string(),
                 std::strerror(rc));
    return false;
  }
  int status = 0;
  pid_t waited = 0;
  while ((waited = waitpid(pid, &status, 0)) < 0 && errno == EINTR) {
  }
  if (waited < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string how = waited < 0            ? fmt::format("cannot wait for it: {}", std::strerror(errno))
                            : WIFEXITED(status)   ? fmt::format("exited with status {}", WEXITSTATUS(status))
                            : WIFSIGNALED(status) ? fmt::format("killed by signal {}", WTERMSIG(status))
                                                  : std::string("stopped");
    spdlog::warn(
        "plot failed ({}: plot_run.py {}; its messages above name the job); the numerical output is "
        "complete",
        names, how);
    return false;
  }
  return true;
}

}  // namespace shellflow::io
