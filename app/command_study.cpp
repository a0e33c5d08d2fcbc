// `shellflow study`: a parameter study of a coupled case with the stability boundary found
// by bracketing and refinement (docs/flutter.md). Every point is a `shellflow run` of the
// same case file with --set overrides, in its own folder, in its own process (up to --jobs
// at once); the growth rate comes from the run's response.json. A point whose folder holds a
// finished point.json is not rerun, so an interrupted study continues where it stopped; a
// point whose run stopped with a checkpoint (Ctrl-C, SIGTERM) continues from it
// (--restart, docs/restart.md).
#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <sstream>

#include "commands.h"
#include "shellflow/core/error.h"
#include "shellflow/core/json.h"
#include "shellflow/io/checkpoint.h"
#include "shellflow/run/run_control.h"

extern "C" char** environ;

namespace shellflow::app {
namespace {

namespace fs = std::filesystem;

/// SIGINT/SIGTERM to the study: no new runs; the running ones stop with a checkpoint.
volatile std::sig_atomic_t g_study_signal = 0;
extern "C" void on_study_signal(int sig) { g_study_signal = sig; }

/// Whether a point's folder holds a checkpoint to continue from.
bool has_checkpoint(const fs::path& dir) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!name.ends_with(".tmp") && io::is_checkpoint_name(name)) return true;
  }
  return false;
}

/// What a point run gave.
struct Point {
  double value = 0.0;
  bool ok = false;
  std::string message;  ///< failed: the run's error line
  double growth_rate = std::nan(""), growth_rate_error = std::nan(""), frequency_hz = std::nan("");
  bool saturated = false;
  double lco_amplitude = std::nan(""), lco_frequency_hz = std::nan("");
  fs::path dir;
};

std::string slurp(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

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

/// A CSV field in double quotes (quotes doubled, line breaks dropped).
std::string csv_quoted(const std::string& s) {
  std::string out = "\"";
  for (const char ch : s) {
    if (ch == '\n' || ch == '\r') continue;
    out += ch == '"' ? "\"\"" : std::string(1, ch);
  }
  return out + "\"";
}

/// Reads a finished point's folder: point.json (status) and response.json (rates).
std::optional<Point> read_point(const fs::path& dir, double value) {
  if (!fs::exists(dir / "point.json")) return std::nullopt;
  const std::string status = slurp(dir / "point.json");
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
  const std::string r = slurp(dir / "response.json");
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

/// Every --set of a point's run: the command line's, the study's `set`, then the parameter's.
std::vector<std::string> run_overrides(const io::Case& c, const CommonOptions& common, double value) {
  std::vector<std::string> out = common.overrides;
  for (const auto& o : c.study->set) out.push_back(o.path + "=" + o.value);
  for (const auto& o : overrides_of(c, value)) out.push_back(o);
  return out;
}

class PointRunner {
 public:
  PointRunner(const io::Case& c, const CommonOptions& common, fs::path root, int jobs)
      : c_(c), common_(common), root_(std::move(root)), jobs_(jobs) {
    char buffer[4096];
    const ssize_t n = readlink("/proc/self/exe", buffer, sizeof buffer - 1);
    if (n <= 0) throw Error("study: cannot find the shellflow executable (/proc/self/exe)");
    exe_.assign(buffer, std::size_t(n));
  }

  fs::path dir_of(double value) const {
    return root_ / "points" / fmt::format("{}_{:.8g}", io::to_string(c_.study->parameter), value);
  }

  /// Runs the values not yet finished, `jobs` at a time; returns every value's point.
  std::vector<Point> run(const std::vector<double>& values) {
    std::vector<Point> out;
    std::vector<double> todo;
    for (const double v : values) {
      // A point of an earlier study with other settings (the case file, --set, study.set) is rerun.
      if (fs::exists(dir_of(v) / "point.json") && slurp(dir_of(v) / "settings.txt") != settings(v)) {
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

 private:
  /// What makes a point's run: the case file's text and the run's overrides (not those of
  /// `study.*`, which `run` ignores: a study refined with another tolerance reuses its points).
  std::string settings(double value) const {
    std::string text = slurp(common_.case_file);
    for (const auto& o : run_overrides(c_, common_, value))
      if (!o.starts_with("study.")) text += "\n--set " + o;
    return text;
  }

  pid_t spawn(double value) {
    const fs::path dir = dir_of(value);
    fs::create_directories(dir);
    // An interrupted run of the same settings continues from its checkpoint.
    const bool resume = slurp(dir / "settings.txt") == settings(value) && has_checkpoint(dir);
    std::ofstream(dir / "settings.txt", std::ios::binary) << settings(value);
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
    const std::string log = (dir / "run.log").string();
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    // A continued run appends to the log of the run it continues.
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                     O_WRONLY | O_CREAT | (resume ? O_APPEND : O_TRUNC), 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, exe_.c_str(), &actions, nullptr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) throw Error(fmt::format("study: cannot start {} ({})", exe_, std::strerror(rc)));
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
      std::istringstream log(slurp(dir / "run.log"));
      for (std::string line; std::getline(log, line);)
        if (line.find("error:") != std::string::npos) message = line;
      if (message.empty())
        message = WIFSIGNALED(status) ? fmt::format("killed by signal {}", WTERMSIG(status))
                                      : fmt::format("exit status {}", WEXITSTATUS(status));
    }
    std::ofstream(dir / "point.json") << fmt::format("{{\"value\": {}, \"ok\": {}, \"message\": {}}}\n",
                                                     json_number(value), ok ? "true" : "false", json_string(message));
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

/// The first sign change of the growth rate among the finished points, by value.
std::optional<std::pair<Point, Point>> bracket(const std::vector<Point>& points) {
  std::vector<Point> ok;
  for (const auto& p : points)
    if (p.ok) ok.push_back(p);
  std::sort(ok.begin(), ok.end(), [](const Point& a, const Point& b) { return a.value < b.value; });
  for (std::size_t i = 1; i < ok.size(); ++i)
    if ((ok[i - 1].growth_rate < 0.0) != (ok[i].growth_rate < 0.0)) return std::pair{ok[i - 1], ok[i]};
  return std::nullopt;
}

double zero_of(const Point& a, const Point& b) {
  return a.value - a.growth_rate * (b.value - a.value) / (b.growth_rate - a.growth_rate);
}

/// The study section and the case as the runs will read it at both ends of the range:
/// refused here, not per run.
void check_study_case(const io::Case& c, const CommonOptions& common) {
  if (!c.study)
    throw InputError(
        fmt::format("{}: the case has no 'study' section (parameter, range, points, tolerance; "
                    "docs/case-format.md)",
                    common.case_file.string()));
  const io::StudySection& s = *c.study;
  if (!io::response_probe(c))
    throw InputError(
        fmt::format("{}: a study reads the growth rate of a shell.displacement probe; add one to "
                    "'probes' (or name it in coupling.response.probe)",
                    common.case_file.string()));
  for (const double v : {s.lo, s.hi}) {
    CommonOptions point = common;
    point.overrides = run_overrides(c, common, v);
    try {
      (void)read_case(point);
    } catch (const InputError& e) {
      throw InputError(fmt::format("study at {} = {:.8g} (study.set and the parameter applied): {}",
                                   io::to_string(s.parameter), v, e.what()));
    }
  }
}

/// SIGINT/SIGTERM stop a study (its runs get the signal too and stop with checkpoints) while
/// an object of this type lives; the previous handlers come back with its end.
class StudySignals {
 public:
  StudySignals() {
    g_study_signal = 0;
    struct sigaction action {};
    action.sa_handler = on_study_signal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &old_int_);
    sigaction(SIGTERM, &action, &old_term_);
  }
  ~StudySignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  StudySignals(const StudySignals&) = delete;
  StudySignals& operator=(const StudySignals&) = delete;

 private:
  struct sigaction old_int_ {
  }, old_term_{};
};

/// Where the study stands after its runs: every point, the bracket of the sign change, the
/// refinement rounds made.
struct StudyResult {
  std::vector<Point> points;
  std::optional<std::pair<Point, Point>> bracket;
  int rounds = 0;
  bool stopped = false;
};

/// Refinement: regula falsi (Illinois) on the bracket, with `jobs` points per round (the
/// secant estimate first, the others splitting the bracket evenly).
void refine(const io::StudySection& s, int jobs, PointRunner& runner, const std::function<bool()>& stopped,
            StudyResult& r) {
  double weight_a = 1.0, weight_b = 1.0;  // Illinois: an end kept twice in a row counts half
  int last_kept = -1;                     // 0: a, 1: b
  while (r.bracket && r.bracket->second.value - r.bracket->first.value > s.tolerance && r.rounds < s.max_refinements) {
    const Point a = r.bracket->first, b = r.bracket->second;
    const double w = b.value - a.value;
    const double ga = a.growth_rate * weight_a, gb = b.growth_rate * weight_b;
    double x = a.value - ga * w / (gb - ga);
    x = std::clamp(x, a.value + 0.05 * w, b.value - 0.05 * w);
    std::vector<double> next{x};
    for (int k = 1; k < jobs; ++k) next.push_back(a.value + w * k / jobs);
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end(), [&](double p, double q) { return std::abs(p - q) < 1e-3 * w; }),
               next.end());
    const auto fresh = runner.run(next);
    if ((r.stopped = stopped())) return;
    r.points.insert(r.points.end(), fresh.begin(), fresh.end());
    ++r.rounds;
    const auto nb = bracket(r.points);
    if (!nb) return;
    const bool a_kept = nb->first.value == a.value, b_kept = nb->second.value == b.value;
    const int kept = a_kept && !b_kept ? 0 : b_kept && !a_kept ? 1 : -1;
    weight_a = kept == 0 ? (last_kept == 0 ? 0.5 * weight_a : weight_a) : 1.0;
    weight_b = kept == 1 ? (last_kept == 1 ? 0.5 * weight_b : weight_b) : 1.0;
    last_kept = kept;
    if (a_kept && b_kept) {
      spdlog::warn("study: the runs inside [{:.8g}, {:.8g}] failed; the bracket stays", a.value, b.value);
      return;
    }
    r.bracket = nb;
  }
}

/// study.csv and study.json (returned, for --json).
std::string write_results(const io::Case& c, const StudyResult& r, const std::optional<double>& boundary,
                          const fs::path& outdir) {
  const io::StudySection& s = *c.study;
  const std::string name(io::to_string(s.parameter));
  {
    std::ofstream csv(outdir / "study.csv");
    csv << name
        << ",status,growth_rate,growth_rate_error,frequency_hz,saturated,lco_amplitude,lco_frequency_hz,"
           "folder,message\n";
    for (const auto& p : r.points)
      csv << fmt::format("{:.10g},{},{},{},{},{},{},{},{},{}\n", p.value, p.ok ? "ok" : "failed",
                         json_number(p.growth_rate), json_number(p.growth_rate_error), json_number(p.frequency_hz),
                         p.saturated ? 1 : 0, json_number(p.lco_amplitude), json_number(p.lco_frequency_hz),
                         fs::relative(p.dir, outdir).string(), csv_quoted(p.message));
  }
  std::string rows;
  for (const auto& p : r.points)
    rows += fmt::format(
        "{}{{\"value\": {}, \"ok\": {}, \"growth_rate\": {}, \"growth_rate_error\": {}, "
        "\"frequency_hz\": {}, \"saturated\": {}, \"lco_amplitude\": {}, \"lco_frequency_hz\": {}, "
        "\"message\": {}}}",
        rows.empty() ? "" : ", ", json_number(p.value), p.ok ? "true" : "false", json_number(p.growth_rate),
        json_number(p.growth_rate_error), json_number(p.frequency_hz), p.saturated ? "true" : "false",
        json_number(p.lco_amplitude), json_number(p.lco_frequency_hz), json_string(p.message));
  const auto& br = r.bracket;
  const std::string json = fmt::format(
      "{{\"case\": {}, \"parameter\": \"{}\", \"range\": [{}, {}], \"tolerance\": {}, \"boundary\": {}, "
      "\"bracket\": {}, \"refinements\": {}, \"points\": [{}]}}",
      json_string(c.name), name, json_number(s.lo), json_number(s.hi), json_number(s.tolerance),
      boundary ? json_number(*boundary) : "null",
      br ? fmt::format("[{}, {}]", json_number(br->first.value), json_number(br->second.value)) : "null", r.rounds,
      rows);
  std::ofstream(outdir / "study.json") << json << '\n';
  return json;
}

/// The boundary found, or why there is none.
void log_outcome(const io::StudySection& s, const StudyResult& r, const std::optional<double>& boundary) {
  const std::string name(io::to_string(s.parameter));
  if (boundary) {
    spdlog::info("study: flutter boundary at {} = {:.6g} (bracket [{:.6g}, {:.6g}], {} refinement round(s))", name,
                 *boundary, r.bracket->first.value, r.bracket->second.value, r.rounds);
    return;
  }
  std::string found;
  for (const auto& p : r.points)
    found += fmt::format("{}{:.6g}: {}", found.empty() ? "" : ", ", p.value,
                         p.ok ? fmt::format("{:.4g} 1/s", p.growth_rate) : "failed");
  spdlog::warn("study: the growth rate does not change sign in {} = [{:.6g}, {:.6g}] ({}); widen study.range", name,
               s.lo, s.hi, found);
}

}  // namespace

int study_command(const CommonOptions& common, const StudyOptions& options) {
  // 1. The case and its study, checked at both ends of the range.
  const io::Case c = read_case(common);
  check_study_case(c, common);
  const io::StudySection& s = *c.study;
  const auto outdir = prepare_output_dir(c, common);
  spdlog::info("study of '{}': {} in [{:.6g}, {:.6g}], {} points, boundary to {:.3g}, {} job(s) -> {}", c.name,
               io::to_string(s.parameter), s.lo, s.hi, s.points, s.tolerance, options.jobs, outdir.string());
  // 2. The runs: the points of the range, then the refinement of the sign change.
  PointRunner runner(c, common, outdir, options.jobs);
  const StudySignals signals;
  const auto stopped = [&] {
    if (!runner.interrupted() && g_study_signal == 0) return false;
    spdlog::warn(
        "study interrupted: the finished points are kept and the stopped runs have checkpoints; run the "
        "same command again to continue");
    return true;
  };
  std::vector<double> values;
  for (int i = 0; i < s.points; ++i) values.push_back(s.lo + (s.hi - s.lo) * i / (s.points - 1));
  StudyResult result;
  result.points = runner.run(values);
  if (stopped()) return kStoppedExitCode;
  result.bracket = bracket(result.points);
  refine(s, options.jobs, runner, stopped, result);
  if (result.stopped) return kStoppedExitCode;
  // 3. The results, the boundary and the plot.
  std::sort(result.points.begin(), result.points.end(),
            [](const Point& a, const Point& b) { return a.value < b.value; });
  std::optional<double> boundary;
  if (result.bracket) boundary = zero_of(result.bracket->first, result.bracket->second);
  const std::string json = write_results(c, result, boundary, outdir);
  log_outcome(s, result, boundary);
  spdlog::info("wrote {}: study.csv, study.json, points/", outdir.string());
  if (options.json) std::printf("%s\n", json.c_str());
  if (common.plot)
    make_plot("plot_study.py",
              {(outdir / "study.csv").string(), "--summary", (outdir / "study.json").string(), "-o", outdir.string()},
              options.json);
  return 0;
}

}  // namespace shellflow::app
