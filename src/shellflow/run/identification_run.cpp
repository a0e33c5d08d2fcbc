// The forced-motion identification run (coupling/forced_motion.h; docs/flutter.md,
// "Identified aerodynamics"): the case's coupled system with the wall driven by pulses of the
// shell's in-vacuo modes, the shell not solved; gaf_record.csv and gaf.json.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>

#include "shellflow/core/json.h"
#include "shellflow/core/output_file.h"
#include "shellflow/coupling/forced_motion.h"
#include "shellflow/coupling/linear_flutter.h"
#include "shellflow/run/run_kinds.h"
#include "shellflow/run/time_loop.h"

namespace shellflow::run {
namespace {

/// gaf_record.csv: time, q_1..q_K, dq_1..dq_K, f_1..f_K, to round-trip precision.
void write_record(const coupling::ForcedMotionRecord& r, const std::filesystem::path& file) {
  const Eigen::Index K = r.forces.empty() ? 0 : r.forces.front().size();
  std::string csv = "time";
  for (const char* name : {"q", "dq", "f"})
    for (Eigen::Index j = 0; j < K; ++j) csv += fmt::format(",{}_{}", name, j + 1);
  csv += '\n';
  for (std::size_t n = 0; n < r.time.size(); ++n) {
    csv += fmt::format("{:.17g}", r.time[n]);
    for (const double x : r.inputs[n]) csv += fmt::format(",{:.17g}", x);
    for (const double x : r.forces[n]) csv += fmt::format(",{:.17g}", x);
    csv += '\n';
  }
  write_file_atomically(file, csv);
}

/// gaf_modes.csv: the modes' vectors in the shell's dofs (a row per dof, a column per mode),
/// against which a case of another thickness or material is checked before its reuse.
void write_modes(const Eigen::MatrixXd& basis, const std::filesystem::path& file) {
  std::string csv = "dof";
  for (Eigen::Index j = 0; j < basis.cols(); ++j) csv += fmt::format(",mode_{}", j + 1);
  csv += '\n';
  for (Eigen::Index i = 0; i < basis.rows(); ++i) {
    csv += std::to_string(i);
    for (Eigen::Index j = 0; j < basis.cols(); ++j) csv += fmt::format(",{:.17g}", basis(i, j));
    csv += '\n';
  }
  write_file_atomically(file, csv);
}

/// gaf.json: what the record belongs to (the flutter command checks it before reusing it).
void write_summary(const RunContext& run, const coupling::ForcedModalMotion& forced,
                   const coupling::LinearFlutterSystem& modes, const coupling::FlowCondition& flow,
                   const std::string& aerodynamics) {
  std::string freqs, peaks;
  for (const double f : modes.in_vacuo_frequencies()) freqs += (freqs.empty() ? "" : ", ") + json_number(f);
  for (const double p : forced.pulses().peak) peaks += (peaks.empty() ? "" : ", ") + json_number(p);
  write_file_atomically(
      run.outdir / "gaf.json",
      fmt::format("{{\"case\": {}, \"case_sections\": {}, \"aerodynamics\": {}, \"modes\": {}, \"dt\": {:.17g}, "
                  "\"steps\": {}, \"pulse_width\": {:.17g}, \"gap\": {:.17g}, \"amplitude\": {}, \"peaks\": [{}], "
                  "\"in_vacuo_frequencies_hz\": [{}], \"density\": {:.17g}, \"speed\": {:.17g}, \"mach\": {:.17g}, "
                  "\"dynamic_pressure_over_beta\": {:.17g}}}\n",
                  json_string(run.c.name), json_string(case_sections_digest(run.c)), json_string(aerodynamics),
                  modes.size(), forced.record().dt, forced.steps(), forced.pulses().width, forced.pulses().gap,
                  json_number(run.c.coupling->identification->amplitude), peaks, freqs, flow.density, flow.speed,
                  flow.mach, flow.dynamic_pressure_over_beta));
}

}  // namespace

std::string case_sections_digest(const io::Case& c) {
  std::string text;
  for (const io::SectionDigest& d : c.digests)
    text += fmt::format("{}{}:{:016x}", text.empty() ? "" : " ", d.name, d.digest);
  return text;
}

void run_identification(const RunContext& run) {
  const io::Case& c = run.c;
  const io::CouplingSection::Identification& id = *c.coupling->identification;
  if (!c.probes.empty())
    io::throw_at(id.where,
                 "an identification run records the modal forces (gaf_record.csv), not probes: remove the 'probes' "
                 "section (shellflow flutter --aerodynamics identified leaves them out itself)");
  CoupledBuild built(run);
  setup::CoupledSystem& s = built.system;
  // 1. The modes, the pulses and the stream.
  const coupling::LinearFlutterSystem modes(*s.shell, id.modes);
  const coupling::FlutterSetting setting = setup::flutter_setting(c, *s.shell);
  const coupling::FlowCondition flow = setting.flow(coupling::FlutterParameter::mach, setting.mach);
  const double dt = c.time->step;
  const double sound = std::sqrt(setting.gamma * setting.pressure / setting.density);
  const double width = id.pulse_width > 0.0 ? id.pulse_width : 1.0 / modes.in_vacuo_frequencies().back();
  const double gap = id.gap > 0.0 ? id.gap : 3.0 * setting.length / (sound * std::max(setting.mach - 1.0, 0.1));
  coupling::ForcedModalMotion forced(*s.shell, modes.basis(), width, gap, id.amplitude, dt, *s.aerodynamics, *s.motion);
  spdlog::info(
      "identification run: {} in-vacuo modes ({:.5g} ... {:.5g} Hz), a raised-cosine pulse of displacement and one "
      "of velocity each, {:.4g} ms long, {:.4g} ms apart, peak deflection {:.3g} m; aerodynamics '{}'; {} shell steps "
      "of {:.4g} s, no shell solve",
      id.modes, modes.in_vacuo_frequencies().front(), modes.in_vacuo_frequencies().back(), 1e3 * width,
      1e3 * (width + gap), id.amplitude, s.aerodynamics->name(), forced.total_steps(), dt);
  // 2. The steps (checkpointed like every run).
  TimeStepping stepping;
  stepping.kind = "identification";
  stepping.loop = {forced.total_steps(), c.output.every, double(forced.total_steps()) * dt, run.outdir, {}};
  stepping.advance = [&forced](long) {
    forced.step();
    return forced.time();
  };
  stepping.time = [&forced] { return forced.time(); };
  stepping.save = [&forced](ArchiveWriter& out) { forced.save(out); };
  stepping.restore = [&forced](ArchiveReader& in) { forced.restore(in); };
  step_in_time(run.control, run.recorder, stepping);
  if (run.control.stopped()) return;
  // 3. The record.
  write_record(forced.record(), run.outdir / "gaf_record.csv");
  write_modes(modes.basis(), run.outdir / "gaf_modes.csv");
  write_summary(run, forced, modes, flow, s.aerodynamics->name());
  spdlog::info("wrote {}: gaf_record.csv ({} samples), gaf_modes.csv, gaf.json", run.outdir.string(),
               forced.record().time.size());
}

}  // namespace shellflow::run
