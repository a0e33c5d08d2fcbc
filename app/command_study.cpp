// `shellflow study`: a parameter study of a coupled case with the stability boundary found
// by bracketing and refinement (docs/flutter.md). Every point is a `shellflow run` of the
// same case file with --set overrides, in its own folder, in its own process (up to --jobs
// at once); the growth rate comes from the run's response.json. A point whose folder holds a
// finished point.json is not rerun, so an interrupted study continues where it stopped; a
// point whose run stopped with a checkpoint (Ctrl-C, SIGTERM) continues from it
// (--restart, docs/restart.md).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>

#include "commands.h"
#include "shellflow/core/boundary_search.h"
#include "shellflow/core/error.h"
#include "shellflow/core/json.h"
#include "shellflow/core/output_file.h"
#include "shellflow/io/checkpoint.h"
#include "shellflow/run/run_control.h"
#include "study_points.h"

namespace shellflow::app {
namespace {

using study::Point;
using study::PointRunner;
using study::run_overrides;
using study::StudySignals;

namespace fs = std::filesystem;

/// A CSV field in double quotes (quotes doubled, line breaks dropped).
std::string csv_quoted(const std::string& s) {
  std::string out = "\"";
  for (const char ch : s) {
    if (ch == '\n' || ch == '\r') continue;
    out += ch == '"' ? "\"\"" : std::string(1, ch);
  }
  return out + "\"";
}

/// Where the study stands after its runs: every point, the bracket of the sign change, the
/// refinement rounds made.
struct StudyResult {
  std::vector<Point> points;
  std::optional<std::pair<Point, Point>> bracket;
  int rounds = 0;
  bool stopped = false;
};

/// Refinement of the bracket (core/boundary_search.h), `jobs` points per round.
void refine(const io::StudySection& s, int jobs, PointRunner& runner, const std::function<bool()>& stopped,
            StudyResult& r) {
  IllinoisRefinement refinement(s.tolerance, s.max_refinements, jobs);
  while (r.bracket && refinement.wants_round(r.bracket->first.value, r.bracket->second.value)) {
    const Point a = r.bracket->first, b = r.bracket->second;
    const auto fresh = runner.run(refinement.next_values(a.value, a.growth_rate, b.value, b.growth_rate));
    if ((r.stopped = stopped())) return;
    r.points.insert(r.points.end(), fresh.begin(), fresh.end());
    ++r.rounds;
    const auto nb = first_sign_change(r.points);
    if (!nb) return;
    if (refinement.record(a.value, b.value, nb->first.value, nb->second.value) ==
        IllinoisRefinement::Outcome::stalled) {
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
    std::string csv = name +
                      ",status,growth_rate,growth_rate_error,frequency_hz,saturated,lco_amplitude,lco_frequency_hz,"
                      "folder,message\n";
    for (const auto& p : r.points)
      csv += fmt::format("{:.10g},{},{},{},{},{},{},{},{},{}\n", p.value, p.ok ? "ok" : "failed",
                         json_number(p.growth_rate), json_number(p.growth_rate_error), json_number(p.frequency_hz),
                         p.saturated ? 1 : 0, json_number(p.lco_amplitude), json_number(p.lco_frequency_hz),
                         fs::relative(p.dir, outdir).string(), csv_quoted(p.message));
    write_file_atomically(outdir / "study.csv", csv);
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
  write_file_atomically(outdir / "study.json", json + '\n');
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
  if (std::none_of(r.points.begin(), r.points.end(), [](const Point& p) { return p.ok; }))
    return;  // no result at all: study_command stops with the runs' reason
  std::string found;
  for (const auto& p : r.points)
    found += fmt::format("{}{:.6g}: {}", found.empty() ? "" : ", ", p.value,
                         p.ok ? fmt::format("{:.4g} 1/s", p.growth_rate) : "failed");
  spdlog::warn("study: the growth rate does not change sign in {} = [{:.6g}, {:.6g}] ({}); widen study.range", name,
               s.lo, s.hi, found);
}

}  // namespace

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

int study_command(const CommonOptions& common, const StudyOptions& options) {
  // 1. The case and its study, checked at both ends of the range.
  const io::Case c = read_case(common);
  check_study_case(c, common);
  const io::StudySection& s = *c.study;
  const auto folder = prepare_output_dir(c, common);  // locked while this command runs
  const std::filesystem::path& outdir = folder.path;
  spdlog::info("study of '{}': {} in [{:.6g}, {:.6g}], {} points, boundary to {:.3g}, {} job(s) -> {}", c.name,
               io::to_string(s.parameter), s.lo, s.hi, s.points, s.tolerance, options.jobs, outdir.string());
  // 2. The runs: the points of the range, then the refinement of the sign change.
  PointRunner runner(c, common, outdir, options.jobs);
  const StudySignals signals;
  const auto stopped = [&] {
    if (!runner.interrupted() && !StudySignals::received()) return false;
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
  result.bracket = first_sign_change(result.points);
  refine(s, options.jobs, runner, stopped, result);
  if (result.stopped) return kStoppedExitCode;
  // 3. The results, the boundary and the plot.
  std::sort(result.points.begin(), result.points.end(),
            [](const Point& a, const Point& b) { return a.value < b.value; });
  std::optional<double> boundary;
  if (result.bracket) {
    const auto& [a, b] = *result.bracket;
    boundary = secant_zero(a.value, a.growth_rate, b.value, b.growth_rate);
  }
  const std::string json = write_results(c, result, boundary, outdir);
  log_outcome(s, result, boundary);
  spdlog::info("wrote {}: study.csv, study.json, points/", outdir.string());
  if (options.json) std::printf("%s\n", json.c_str());
  if (common.plot)
    make_plot("plot_study.py",
              {(outdir / "study.csv").string(), "--summary", (outdir / "study.json").string(), "-o", outdir.string()},
              options.json);
  // Points that failed for reasons other than the physics were not recorded: the study is not
  // done until they ran (the same command reruns them).
  std::string rerun;
  long reruns = 0;
  for (const auto& p : result.points)
    if (p.rerun && ++reruns <= 3)
      rerun +=
          fmt::format("{}{} = {:.8g} ({})", rerun.empty() ? "" : "; ", io::to_string(s.parameter), p.value, p.message);
  if (reruns > 0)
    throw Error(
        fmt::format("study: {} point(s) failed for reasons other than the physics and were not recorded: {}{}; "
                    "remove the cause and run the same command again to run them",
                    reruns, rerun, reruns > 3 ? "; ..." : ""));
  // No growth rate anywhere is no result: the reason the runs gave, not a bracket to widen.
  const auto ok = std::count_if(result.points.begin(), result.points.end(), [](const Point& p) { return p.ok; });
  if (ok == 0 && !result.points.empty())
    throw Error(fmt::format("study: none of the {} runs gave a growth rate (at {} = {:.6g}: {}); see {}",
                            result.points.size(), io::to_string(s.parameter), result.points.front().value,
                            result.points.front().message, (outdir / "study.csv").string()));
  return 0;
}

Command add_study_command(CLI::App& cli, CommonOptions& common) {
  auto options = std::make_shared<StudyOptions>();
  auto* sub =
      cli.add_subcommand("study",
                         "Parameter study of a coupled case (its 'study' section: Mach, density, dynamic pressure "
                         "or thickness over a range): one run per point, growth rates from response.json, the "
                         "stability boundary bracketed and refined; study.csv, study.json, study_growth.png, "
                         "study_lco.png; finished points are not rerun");
  add_case_options(sub, common);
  add_output_options(sub, common);
  sub->add_option("-j,--jobs", options->jobs,
                  "Runs at once, one process each (each with one OpenMP thread "
                  "when > 1 unless OMP_NUM_THREADS is set)")
      ->check(CLI::Range(1, 256));
  sub->add_flag("--json", options->json, "Print study.json on stdout and nothing else");
  return {sub, [&common, options] { return study_command(common, *options); }};
}

}  // namespace shellflow::app
