// The points of `shellflow study` (study_points.h): one `shellflow run` process per value, in
// its own folder, up to --jobs at once.
#include "study_points.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "shellflow/core/error.h"
#include "shellflow/core/json.h"
#include "shellflow/core/output_file.h"
#include "shellflow/io/checkpoint.h"

extern "C" char** environ;

namespace shellflow::app::study {

namespace fs = std::filesystem;

namespace {

/// SIGINT/SIGTERM to the study: no new runs; the running ones stop with a checkpoint.
volatile std::sig_atomic_t g_study_signal = 0;
extern "C" void on_study_signal(int sig) { g_study_signal = sig; }

/// The number after `"key":` in `json` at or after `from` (our own files: flat, no escapes
/// in the keys); NaN when absent or null.
double read_json_number(const std::string& json, std::string_view key, std::size_t from = 0) {
  const std::string needle = fmt::format("\"{}\":", key);
  const auto at = json.find(needle, from);
  if (at == std::string::npos) return std::nan("");
  auto p = at + needle.size();
  while (p < json.size() && json[p] == ' ') ++p;
  double x = std::nan("");
  const auto [end, ec] = std::from_chars(json.data() + p, json.data() + json.size(), x);
  return ec == std::errc() ? x : std::nan("");
}

bool json_true(const std::string& json, std::string_view key) {
  const std::string needle = fmt::format("\"{}\":", key);
  const auto at = json.find(needle);
  if (at == std::string::npos) return false;
  const auto v = json.find_first_not_of(' ', at + needle.size());
  return v != std::string::npos && json.compare(v, 4, "true") == 0;
}

/// Reads a finished point's folder: point.json (status) and response.json (rates).
std::optional<Point> read_point(const fs::path& dir, double value) {
  if (!fs::exists(dir / "point.json")) return std::nullopt;
  const std::string status = read_text_file(dir / "point.json");
  Point p;
  p.value = value;
  p.dir = dir;
  p.ok = json_true(status, "ok");
  if (auto m = status.find("\"message\": \""); m != std::string::npos) {
    // Written by json_string: undo the \" and \\ escapes (messages hold no control characters).
    for (m += 12; m < status.size() && status[m] != '"'; ++m) {
      if (status[m] == '\\' && m + 1 < status.size()) ++m;
      p.message += status[m];
    }
  }
  if (!p.ok) return p;
  const std::string r = read_text_file(dir / "response.json");
  p.growth_rate = read_json_number(r, "growth_rate");
  p.growth_rate_error = read_json_number(r, "growth_rate_error");
  p.frequency_hz = read_json_number(r, "frequency_hz");
  p.saturated = json_true(r, "saturated");
  if (const auto lco = r.find("\"lco\": {"); lco != std::string::npos) {
    p.lco_amplitude = read_json_number(r, "amplitude", lco);
    p.lco_frequency_hz = read_json_number(r, "frequency_hz", lco);
  }
  if (!std::isfinite(p.growth_rate)) {
    p.ok = false;
    p.message =
        "response.json has no growth rate (too few extrema in the fit window: run longer or widen "
        "coupling.response.window)";
  }
  return p;
}

/// Starts `exe argv` with `envp`, its output to `log` (appended to when `resume`): fork and
/// exec (posix_spawn cannot set a parent-death signal), the child getting SIGTERM when the
/// study dies, even by SIGKILL: a point run stops at its next step with a checkpoint rather
/// than run on, orphaned, in a folder the next study would share with it. Between fork and
/// exec the child calls only async-signal-safe functions; an exec failure comes back through
/// a close-on-exec pipe.
pid_t start_point_run(const std::string& exe, const std::string& log, bool resume, char* const* argv,
                      char* const* envp) {
  int report[2];
  if (pipe2(report, O_CLOEXEC) != 0) throw Error(fmt::format("study: cannot start {} ({})", exe, std::strerror(errno)));
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    close(report[0]);
    int err = 0;
    if (prctl(PR_SET_PDEATHSIG, SIGTERM) != 0 || getppid() != parent) err = ESRCH;  // the study is gone already
    // A continued run appends to the log of the run it continues.
    const int fd = err ? -1 : open(log.c_str(), O_WRONLY | O_CREAT | O_NOFOLLOW | (resume ? O_APPEND : O_TRUNC), 0644);
    if (!err && fd < 0) err = errno;
    if (!err && (dup2(fd, STDOUT_FILENO) < 0 || dup2(fd, STDERR_FILENO) < 0)) err = errno;
    if (!err) {
      if (fd > STDERR_FILENO) close(fd);
      execve(exe.c_str(), argv, envp);
      err = errno;
    }
    [[maybe_unused]] const ssize_t n = write(report[1], &err, sizeof err);
    _exit(127);
  }
  const int fork_errno = errno;
  close(report[1]);
  int err = 0;
  if (pid > 0) {
    ssize_t n = 0;
    while ((n = read(report[0], &err, sizeof err)) < 0 && errno == EINTR) {
    }
    if (n != sizeof err) err = 0;  // closed by the exec: the run started
  } else {
    err = fork_errno;
  }
  close(report[0]);
  if (err != 0) {
    if (pid > 0) waitpid(pid, nullptr, 0);
    throw Error(fmt::format("study: cannot start {} with its log {} ({})", exe, log, std::strerror(err)));
  }
  return pid;
}

/// The case keys a parameter value sets.
std::vector<std::string> overrides_of(const io::Case& c, double value) {
  switch (c.study->parameter) {
    case io::StudySection::Parameter::mach:
      return {fmt::format("fluid.free_stream.mach={:.12g}", value)};
    case io::StudySection::Parameter::density:
      return {fmt::format("fluid.free_stream.density={:.12g}", value)};
    case io::StudySection::Parameter::thickness:
      return {fmt::format("shell.thickness={:.12g}", value)};
    case io::StudySection::Parameter::dynamic_pressure: {
      // q = rho U^2 / 2 = gamma p M^2 / 2 at the case's p (and rho, so the cavity stays balanced).
      const double m = std::sqrt(2.0 * value / (c.fluid->gas.gamma * c.fluid->free_stream.pressure));
      return {fmt::format("fluid.free_stream.mach={:.12g}", m)};
    }
  }
  return {};
}

}  // namespace

/// Every --set of a point's run: the study's `set`, then the command line's (an explicit
/// --set wins over the case file's study.set), then the parameter's.
std::vector<std::string> run_overrides(const io::Case& c, const CommonOptions& common, double value) {
  std::vector<std::string> out;
  for (const auto& o : c.study->set) out.push_back(o.path + "=" + o.value);
  out.insert(out.end(), common.overrides.begin(), common.overrides.end());
  for (const auto& o : overrides_of(c, value)) out.push_back(o);
  return out;
}

struct PointRunner::Impl {
  Impl(const io::Case& c, const CommonOptions& common, fs::path root, int jobs)
      : c_(c), common_(common), root_(std::move(root)), jobs_(jobs) {
    char buffer[4096];
    const ssize_t n = readlink("/proc/self/exe", buffer, sizeof buffer - 1);
    if (n <= 0) throw Error("study: cannot find the shellflow executable (/proc/self/exe)");
    exe_.assign(buffer, std::size_t(n));
  }

  fs::path dir_of(double value) const {
    // The value as its run is given it (12 significant digits, overrides_of): distinct runs
    // never share a folder (8 digits did: two points of a refinement wrote into one).
    return root_ / "points" / fmt::format("{}_{:.12g}", io::to_string(c_.study->parameter), value);
  }

  /// Runs the values not yet finished, `jobs` at a time; returns every value's point.
  std::vector<Point> run(const std::vector<double>& values) {
    std::vector<Point> out;
    std::vector<double> todo;
    for (const double v : values) {
      // A point of an earlier study with other settings (the case file, --set, study.set) is rerun.
      if (fs::exists(dir_of(v) / "point.json") && read_text_file(dir_of(v) / "settings.txt") != settings(v)) {
        spdlog::info("study: {} = {:.8g} was run with other settings; rerun", io::to_string(c_.study->parameter), v);
        fs::remove(dir_of(v) / "point.json");
      }
      if (auto p = read_point(dir_of(v), v)) {
        spdlog::info("study: {} = {:.8g} already done ({}), not rerun", io::to_string(c_.study->parameter), v,
                     p->ok ? "ok" : "failed");
        out.push_back(*p);
      } else {
        todo.push_back(v);
      }
    }
    std::map<pid_t, double> running;
    std::size_t next = 0;
    bool forwarded = false;
    while ((next < todo.size() && g_study_signal == 0) || !running.empty()) {
      while (next < todo.size() && g_study_signal == 0 && static_cast<int>(running.size()) < jobs_) {
        running[spawn(todo[next])] = todo[next];
        ++next;
      }
      if (g_study_signal != 0 && !forwarded) {
        // The runs stop at their next step with a checkpoint (a terminal's Ctrl-C reached
        // them already; a signal to the study alone is passed on).
        for (const auto& [child, value] : running) kill(child, SIGTERM);
        forwarded = true;
      }
      int status = 0;
      const pid_t pid = waitpid(-1, &status, 0);
      if (pid < 0) {
        if (errno == EINTR) continue;
        throw Error(fmt::format("study: waiting for a run failed ({})", std::strerror(errno)));
      }
      const auto it = running.find(pid);
      if (it == running.end()) continue;
      const double v = it->second;
      running.erase(it);
      out.push_back(finish(v, status));
    }
    return out;
  }

  /// Whether a run stopped with a checkpoint (a signal): the study stops too.
  bool interrupted() const { return interrupted_; }

  /// What makes a point's run: the case file's text and the run's overrides (not those of
  /// `study.*`, which `run` ignores: a study refined with another tolerance reuses its points).
  std::string settings(double value) const {
    std::string text = read_text_file(common_.case_file);
    for (const auto& o : run_overrides(c_, common_, value))
      if (!o.starts_with("study.")) text += "\n--set " + o;
    return text;
  }

  pid_t spawn(double value) {
    const fs::path dir = dir_of(value);
    fs::create_directories(dir);
    // An interrupted run of the same settings continues from its checkpoint.
    const bool resume = read_text_file(dir / "settings.txt") == settings(value) && has_checkpoint(dir);
    write_file_atomically(dir / "settings.txt", settings(value));
    std::vector<std::string> words{exe_, "run", common_.case_file.string(), "--no-plot"};
    if (resume)
      words.insert(words.end(), {"--restart", dir.string()});
    else
      words.insert(words.end(), {"-o", dir.string()});
    for (const auto& o : run_overrides(c_, common_, value)) words.insert(words.end(), {"--set", o});
    std::vector<char*> argv;
    for (auto& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    // Several runs at once share the cores: one OpenMP thread each unless the user set it.
    std::vector<std::string> env;
    for (char** e = environ; *e; ++e) env.emplace_back(*e);
    if (jobs_ > 1 && !std::getenv("OMP_NUM_THREADS")) env.emplace_back("OMP_NUM_THREADS=1");
    std::vector<char*> envp;
    for (auto& e : env) envp.push_back(e.data());
    envp.push_back(nullptr);
    const pid_t pid = start_point_run(exe_, (dir / "run.log").string(), resume, argv.data(), envp.data());
    spdlog::info("study: run {} = {:.8g} -> {}{}", io::to_string(c_.study->parameter), value, dir.string(),
                 resume ? " (continued from its checkpoint)" : "");
    return pid;
  }

  Point finish(double value, int status) {
    const fs::path dir = dir_of(value);
    if (WIFEXITED(status) && WEXITSTATUS(status) == kStoppedExitCode) {
      // Stopped with a checkpoint: no point.json, the next study continues it.
      interrupted_ = true;
      spdlog::warn("study: {} = {:.8g} stopped with a checkpoint in {}", io::to_string(c_.study->parameter), value,
                   dir.string());
      return {.value = value, .ok = false, .message = "interrupted", .dir = dir};
    }
    const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    std::string message;
    if (!ok) {
      // The run's one-line error (or how it ended).
      std::istringstream log(read_text_file(dir / "run.log"));
      for (std::string line; std::getline(log, line);)
        if (line.find("error:") != std::string::npos) message = line;
      if (message.empty())
        message = WIFSIGNALED(status) ? fmt::format("killed by signal {}", WTERMSIG(status))
                                      : fmt::format("exit status {}", WEXITSTATUS(status));
    }
    if (!ok && !(WIFEXITED(status) && WEXITSTATUS(status) == kSolverFailedExitCode)) {
      // Not the physics (another process's lock, a full disk, a kill, a bad input): no
      // point.json, so the same command runs it again (from its checkpoint when it has one).
      spdlog::warn("study: {} = {:.8g} failed, not for the physics: {}; not recorded (the same command runs it again)",
                   io::to_string(c_.study->parameter), value, message);
      return {.value = value, .ok = false, .rerun = true, .message = message, .dir = dir};
    }
    write_file_atomically(dir / "point.json",
                          fmt::format("{{\"value\": {}, \"ok\": {}, \"message\": {}}}\n", json_number(value),
                                      ok ? "true" : "false", json_string(message)));
    Point p = read_point(dir, value).value();
    if (p.ok)
      spdlog::info("study: {} = {:.8g}: growth rate {:.5g} +- {:.2g} 1/s, {:.5g} Hz{}",
                   io::to_string(c_.study->parameter), value, p.growth_rate, p.growth_rate_error, p.frequency_hz,
                   p.saturated ? fmt::format(", limit cycle {:.4g}", p.lco_amplitude) : "");
    else
      spdlog::warn("study: {} = {:.8g} failed: {}", io::to_string(c_.study->parameter), value, p.message);
    return p;
  }

  const io::Case& c_;
  const CommonOptions& common_;
  fs::path root_;
  int jobs_ = 1;
  std::string exe_;
  bool interrupted_ = false;
};

PointRunner::PointRunner(const io::Case& c, const CommonOptions& common, std::filesystem::path root, int jobs)
    : impl_(std::make_unique<Impl>(c, common, std::move(root), jobs)) {}
PointRunner::~PointRunner() = default;
std::vector<Point> PointRunner::run(const std::vector<double>& values) { return impl_->run(values); }
bool PointRunner::interrupted() const { return impl_->interrupted(); }

StudySignals::StudySignals() {
  g_study_signal = 0;
  struct sigaction action {};
  action.sa_handler = on_study_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &old_int_);
  sigaction(SIGTERM, &action, &old_term_);
}

StudySignals::~StudySignals() {
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

bool StudySignals::received() { return g_study_signal != 0; }

}  // namespace shellflow::app::study
