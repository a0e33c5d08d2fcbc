// `shellflow flutter`: linear flutter analysis of a case's shell with piston theory
// (coupling/linear_flutter.h, docs/flutter.md): the root locus against lambda or Mach, the
// critical point, flutter_locus.csv, flutter.json and flutter_locus.png.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>

#include "commands.h"
#include "flutter_identified.h"
#include "shellflow/core/error.h"
#include "shellflow/core/json.h"
#include "shellflow/core/output_file.h"
#include "shellflow/coupling/linear_flutter.h"
#include "shellflow/coupling/piston_theory.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/io/mesh_output.h"
#include "shellflow/run/shell_modes.h"
#include "shellflow/setup/coupled_setup.h"
#include "shellflow/setup/shell_setup.h"

namespace shellflow::app {
namespace {

namespace fs = std::filesystem;

/// The case reduced to what the analysis reads: the shell mesh (a coupled case's fluid and
/// space meshes are not generated).
io::Case shell_only(io::Case c) {
  c.meshes.fluid.reset();
  c.meshes.space.reset();
  std::erase_if(c.group_references, [](const io::GroupReference& g) { return g.mesh != "shell"; });
  return c;
}

struct Result {
  coupling::FlutterSweep sweep;
  double lo = 0.0, hi = 0.0;
  std::optional<double> half_modes_critical;  ///< lambda_cr (or M_cr) on the first half of the modes
  std::complex<double> least_stable;          ///< the least stable root at the case's flow
};

/// Piston theory on the case's stream; the wetted face does not enter the linear matrices
/// (sign^2 = 1). Piston theory checks its stream (supersonic, positive density and speed).
coupling::PistonTheory piston_theory(const io::Case& c, const shell::ShellModel& model, const std::string& where) {
  try {
    return coupling::PistonTheory(
        model, setup::piston_flow(c, c.coupling && c.coupling->wet_normal.norm() > 0.0 ? c.coupling->wet_normal
                                                                                       : model.directors()[0]));
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", where, e.what()));
  }
}

/// Progress of the eigenvalue solves on a large system: a line every 10 s.
class SolveProgress {
 public:
  void operator()(int solved) {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < std::chrono::seconds(10)) return;
    last_ = now;
    const double s = std::chrono::duration<double>(now - start_).count();
    spdlog::info(
        "flutter: {} eigenvalue solves in {:.0f} s ({:.2g} s each; a sweep makes its points and about 30 "
        "bisections)",
        total_ + solved, s, s / (total_ + solved));
  }
  /// A sweep of `solved` values ended: the next counts on.
  void add(int solved) { total_ += solved; }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), last_ = start_;
  int total_ = 0;
};

/// A warning before a dense solve that will take long: the full system (--direct) is one
/// dense nonsymmetric eigenvalue problem of twice its dofs per value, O(n^3).
void warn_of_dense_solves(const coupling::LinearFlutterSystem& linear, const FlutterOptions& options) {
  const Eigen::Index n = 2 * linear.size();
  if (n < 2000) return;
  const double each = coupling::dense_eigenvalue_seconds(n);
  spdlog::warn(
      "--direct: the full system has {} dofs, a dense {} x {} eigenvalue problem per value (O(n^3), about {:.0f} s "
      "each on this machine; {} points and about 30 bisections: about {:.1f} h); drop --direct for the modal basis, "
      "which gives the boundary of the lowest modes in seconds",
      linear.size(), n, n, each, options.points, each * (options.points + 30) / 3600.0);
}

/// The sweep over the parameter's range (widened up to three times when no boundary shows and
/// no --range was given), the truncation check on half the modes, the case's least stable root.
Result sweep(const coupling::LinearFlutterSystem& linear, const coupling::ModalAerodynamics& aero,
             const coupling::FlutterSetting& setting, const FlutterOptions& options, int modes) {
  Result r;
  // The full system's highest roots are the mesh's thickness-stretch modes (MHz), which piston
  // theory destabilises: with --direct only the --modes roots of lowest frequency count.
  const int tracked = options.direct ? options.modes : 0;
  const bool by_lambda = options.parameter == coupling::FlutterParameter::lambda;
  const double lambda_case = setting.lambda_of_mach(setting.mach);
  r.lo = options.range ? options.range->first : by_lambda ? 0.0 : 1.2;
  r.hi = options.range ? options.range->second
         : by_lambda   ? std::max(1000.0, 2.0 * lambda_case)
                       : std::max(3.0, 2.0 * setting.mach);
  if (!by_lambda && !(r.lo >= coupling::kPistonTheoryMinMach))
    throw Error(
        fmt::format("--range {} {}: a Mach sweep must stay at or above Mach {} (piston theory's validity "
                    "limit, docs/coupling.md)",
                    r.lo, r.hi, coupling::kPistonTheoryMinMach));
  SolveProgress progress;
  const auto on_value = [&](int solved) { progress(solved); };
  for (int widen = 0;; ++widen) {
    r.sweep = coupling::sweep_flutter(linear, aero, setting, options.parameter, r.lo, r.hi, options.points, 1e-9,
                                      tracked, on_value);
    progress.add(int(r.sweep.points.size()) + (r.sweep.critical ? r.sweep.critical->bisections : 0));
    if (r.sweep.critical || options.range || widen == 3) break;
    spdlog::info("no flutter boundary up to {} = {:.6g}; widening the range", coupling::to_string(options.parameter),
                 r.hi);
    r.hi = r.lo + 2.0 * (r.hi - r.lo);
  }
  if (!options.direct && modes >= 4 && r.sweep.critical) {
    // Truncation check: the same sweep on the first half of the modes.
    const auto half = linear.truncated(modes / 2);
    const auto s = coupling::sweep_flutter(half, *aero.truncated(modes / 2), setting, options.parameter, r.lo, r.hi,
                                           options.points, 1e-9, 0, on_value);
    if (s.critical) r.half_modes_critical = s.critical->value;
  }
  coupling::FlowCondition case_flow = setting.flow(coupling::FlutterParameter::mach, setting.mach);
  case_flow.damping = true;  // the case's own flow has its damping (also with --no-aero-damping)
  auto case_roots = aero.roots(linear, case_flow);
  if (tracked > 0 && case_roots.size() > std::size_t(tracked)) case_roots.resize(std::size_t(tracked));
  r.least_stable = *std::max_element(case_roots.begin(), case_roots.end(),
                                     [](const auto& a, const auto& b) { return a.real() < b.real(); });
  return r;
}

/// flutter_locus.csv: one row per root and parameter value.
void write_locus(const Result& r, const fs::path& outdir) {
  std::string csv = "value,lambda,mach,root,growth_rate,frequency_hz,damping_g\n";
  for (const auto& p : r.sweep.points)
    for (std::size_t k = 0; k < p.eigenvalues.size(); ++k) {
      const auto s = p.eigenvalues[k];
      const double g = s.imag() != 0.0 ? 2.0 * s.real() / s.imag() : std::nan("");
      csv += fmt::format("{:.10g},{:.10g},{},{},{:.10g},{:.10g},{}\n", p.value, p.lambda, json_number(p.mach), k + 1,
                         s.real(), s.imag() / (2.0 * std::numbers::pi), json_number(g));
    }
  write_file_atomically(outdir / "flutter_locus.csv", csv);
}

/// flutter.json (returned, for --json).
std::string write_summary(const io::Case& c, const Result& r, const coupling::LinearFlutterSystem& linear,
                          const coupling::FlutterSetting& setting, const FlutterOptions& options, int modes,
                          const std::string& identification, const fs::path& outdir) {
  const auto& cr = r.sweep.critical;
  const auto& mat = c.shell->material;
  std::string freqs;
  for (const double f : linear.in_vacuo_frequencies()) freqs += (freqs.empty() ? "" : ", ") + json_number(f);
  const std::string json = fmt::format(
      "{{\"case\": {}, \"parameter\": \"{}\", \"range\": [{}, {}], \"points\": {}, \"modes\": {}, "
      "\"aerodynamic_damping\": {}, \"panel_length\": {}, \"bending_stiffness\": {}, \"mu_over_mach\": {}, "
      "\"lambda_case\": {}, \"mach_case\": {}, \"case_growth_rate\": {}, \"case_frequency_hz\": {}, "
      "\"lambda_cr\": {}, \"mach_cr\": {}, \"frequency_hz\": {}, \"critical_value\": {}, "
      "\"critical_value_half_modes\": {}, \"in_vacuo_frequencies_hz\": [{}], \"aerodynamics\": {}, "
      "\"identification\": {}}}",
      json_string(c.name), coupling::to_string(options.parameter), json_number(r.lo), json_number(r.hi), options.points,
      modes, setting.aerodynamic_damping ? "true" : "false", json_number(setting.length),
      json_number(setting.bending_stiffness),
      json_number(setting.mass_ratio_over_mach(mat.density, c.shell->thickness)),
      json_number(setting.lambda_of_mach(setting.mach)), json_number(setting.mach), json_number(r.least_stable.real()),
      json_number(std::abs(r.least_stable.imag()) / (2.0 * std::numbers::pi)), cr ? json_number(cr->lambda) : "null",
      cr ? json_number(cr->mach) : "null", cr ? json_number(cr->frequency_hz) : "null",
      cr ? json_number(cr->value) : "null", r.half_modes_critical ? json_number(*r.half_modes_critical) : "null", freqs,
      identification.empty() ? "\"piston_theory\"" : "\"identified\"",
      identification.empty() ? "null" : identification);
  write_file_atomically(outdir / "flutter.json", json + '\n');
  return json;
}

/// flutter_modes.vtu: the first in-vacuo modes of the basis (`mode_01`, ...) and the flutter
/// mode, the least stable root's shape at the critical point (at the case's flow when the
/// range has no boundary), as its real and imaginary parts (`flutter_mode_re`, `_im`; the
/// largest displacement component is real and 1). Modal basis only.
void write_mode_shapes(const shell::ShellModel& model, const coupling::LinearFlutterSystem& linear,
                       const coupling::ModalAerodynamics& aero, const Result& r,
                       const coupling::FlutterSetting& setting, const FlutterOptions& options, const fs::path& outdir) {
  constexpr int shown = 6;
  const Index nodes = model.num_nodes();
  const Eigen::Index count = std::min<Eigen::Index>(shown, linear.basis().cols());
  std::vector<std::vector<double>> values;  // VtuField views these
  values.reserve(std::size_t(count) + 2);
  std::vector<io::VtuField> fields;
  for (Eigen::Index k = 0; k < count; ++k) {
    values.push_back(run::normalised_mode_displacement(linear.basis().col(k), nodes));
    fields.push_back({fmt::format("mode_{:02}", k + 1), 3, values.back()});
  }
  const coupling::FlowCondition flow = r.sweep.critical ? setting.flow(options.parameter, r.sweep.critical->value)
                                                        : setting.flow(coupling::FlutterParameter::mach, setting.mach);
  const Eigen::VectorXcd shape = aero.least_stable_mode(linear, flow).second;
  std::vector<double> re, im;
  for (Index n = 0; n < nodes; ++n)
    for (int i = 0; i < 3; ++i) {
      re.push_back(shape(shell::dofs_per_node * n + i).real());
      im.push_back(shape(shell::dofs_per_node * n + i).imag());
    }
  values.push_back(std::move(re));
  fields.push_back({"flutter_mode_re", 3, values.back()});
  values.push_back(std::move(im));
  fields.push_back({"flutter_mode_im", 3, values.back()});
  io::write_mesh_vtu(outdir / "flutter_modes.vtu", model.mesh(), std::move(fields));
}

/// The boundary found (or the advice to widen the range) and the case's least stable root.
void log_outcome(const Result& r, const coupling::FlutterSetting& setting, const FlutterOptions& options, int modes,
                 const fs::path& outdir) {
  if (const auto& cr = r.sweep.critical) {
    spdlog::info(
        "flutter boundary: lambda_cr = {:.6g}, Mach_cr = {:.6g} (at rho = {:.6g} kg/m^3, p = {:.6g} Pa), "
        "{:.6g} Hz{}",
        cr->lambda, cr->mach, setting.density, setting.pressure, cr->frequency_hz,
        r.half_modes_critical ? fmt::format(" ({} modes: {} = {:.6g})", modes / 2,
                                            coupling::to_string(options.parameter), *r.half_modes_critical)
                              : "");
  } else {
    spdlog::warn("no flutter boundary in {} = [{:.6g}, {:.6g}]; give a wider --range",
                 coupling::to_string(options.parameter), r.lo, r.hi);
  }
  spdlog::info(
      "the case's flow (lambda = {:.6g}, Mach {:.4g}): least stable root {:.6g} 1/s at {:.6g} Hz; wrote "
      "{}: flutter_locus.csv, flutter.json{}",
      setting.lambda_of_mach(setting.mach), setting.mach, r.least_stable.real(),
      std::abs(r.least_stable.imag()) / (2.0 * std::numbers::pi), outdir.string(),
      options.direct ? "" : ", flutter_modes.vtu");
}

/// The aerodynamic model of the analysis: piston theory on the case's stream, or the model
/// identified from the case's own flow (flutter_identified.h; empty when its run stopped).
struct Aerodynamics {
  std::unique_ptr<coupling::ModalAerodynamics> model;
  std::string identification;  ///< flutter.json's `identification` (identified only)
};

Aerodynamics aerodynamics(const CommonOptions& common, const FlutterOptions& options, const io::Case& c,
                          const shell::ShellModel& model, const coupling::LinearFlutterSystem& linear,
                          const coupling::FlutterSetting& setting, const fs::path& outdir) {
  Aerodynamics a;
  if (options.aerodynamics == FlutterOptions::Aerodynamics::piston) {
    a.model =
        std::make_unique<coupling::PistonAerodynamics>(linear, piston_theory(c, model, common.case_file.string()));
    return a;
  }
  IdentifiedModel id = identify(common, options, linear, setting, outdir);
  if (id.stopped) return a;
  a.model = std::move(id.aero);
  a.identification = std::move(id.json);
  return a;
}

/// The options that do not go together, refused before anything runs.
void check_options(const io::Case& full, const FlutterOptions& options, const std::string& where) {
  if (!full.shell)
    throw InputError(fmt::format("{}: the linear flutter analysis needs a 'shell' section (the panel)", where));
  if (!full.fluid)
    throw InputError(
        fmt::format("{}: the linear flutter analysis needs a 'fluid' section with the free stream "
                    "(density, pressure, mach, direction) for piston theory",
                    where));
  if (options.no_aerodynamic_damping && options.parameter == coupling::FlutterParameter::mach)
    throw Error(
        "--no-aero-damping applies to --parameter lambda only (a Mach sweep at fixed density and "
        "pressure has the damping of its speed)");
  if (options.aerodynamics != FlutterOptions::Aerodynamics::identified) {
    if (!options.identification_mach.empty())
      throw Error("--identification-mach applies to --aerodynamics identified (piston theory takes every Mach)");
    return;
  }
  if (options.direct)
    throw Error(
        "--aerodynamics identified works on the modal basis (its modes are the identification's): drop --direct");
  if (options.no_aerodynamic_damping)
    throw Error(
        "--no-aero-damping: an identified model's forces cannot be split into a stiffness and a damping part; it "
        "applies to piston theory only");
}

}  // namespace

int flutter_command(const CommonOptions& common, const FlutterOptions& options) {
  // 1. The case reduced to its shell, the shell model and the setting.
  const io::Case full = read_case(common);
  const auto where = common.case_file.string();
  check_options(full, options, where);
  const io::Case c = shell_only(full);
  const auto folder = prepare_output_dir(c, common);  // locked while this command runs
  const std::filesystem::path& outdir = folder.path;
  const io::CaseMeshes meshes = io::load_case_meshes(c, std::nullopt);
  const shell::ShellModel model = setup::build_shell_model(*c.shell, *meshes.shell);
  coupling::FlutterSetting setting = setup::flutter_setting(c, model);
  setting.aerodynamic_damping = !options.no_aerodynamic_damping;
  // 2. The linear system (in-vacuo modes or the full system), the aerodynamics, the sweep.
  // Identified: the identification's modes (the case's coupling.identification.modes, else 6).
  const bool identified = options.aerodynamics == FlutterOptions::Aerodynamics::identified;
  const int modes = options.direct                                   ? 0
                    : !identified || options.modes_given             ? options.modes
                    : full.coupling && full.coupling->identification ? full.coupling->identification->modes
                                                                     : 6;
  spdlog::info("linear flutter analysis of '{}': panel length {:.6g} m, D = {:.6g} N m, mu/M = {:.4g}, {} ({}, {})",
               c.name, setting.length, setting.bending_stiffness,
               setting.mass_ratio_over_mach(c.shell->material.density, c.shell->thickness),
               modes > 0 ? fmt::format("{} in-vacuo modes", modes) : "full system",
               identified ? "aerodynamics identified from the case's flow" : "piston theory",
               options.no_aerodynamic_damping ? "no aerodynamic damping, mu/M -> 0" : "with aerodynamic damping");
  const coupling::LinearFlutterSystem linear(model, modes);
  if (!options.direct)
    spdlog::info("in-vacuo frequencies: {:.5g} ... {:.5g} Hz", linear.in_vacuo_frequencies().front(),
                 linear.in_vacuo_frequencies().back());
  else
    spdlog::info("full system: {} dofs with mass (thickness parameter condensed)", linear.size());
  if (options.direct) warn_of_dense_solves(linear, options);
  const Aerodynamics aero = aerodynamics(common, options, full, model, linear, setting, outdir);
  if (!aero.model) return run::kStoppedExitCode;  // the identification run stopped with a checkpoint
  const Result r = sweep(linear, *aero.model, setting, options, modes);
  // 3. The outputs and the plot.
  write_locus(r, outdir);
  const std::string json = write_summary(c, r, linear, setting, options, modes, aero.identification, outdir);
  if (!options.direct) write_mode_shapes(model, linear, *aero.model, r, setting, options, outdir);
  log_outcome(r, setting, options, modes, outdir);
  if (options.json) std::printf("%s\n", json.c_str());
  if (common.plot) {
    make_plot("plot_flutter_locus.py",
              {(outdir / "flutter_locus.csv").string(), "--summary", (outdir / "flutter.json").string(), "-o",
               (outdir / "flutter_locus.png").string()},
              options.json);
    if (!options.direct)
      make_plot("plot_shell_field.py",
                {(outdir / "flutter_modes.vtu").string(), "--modes", "--max-panels", "8", "-o",
                 (outdir / "flutter_modes.png").string()},
                options.json);
  }
  return 0;
}

Command add_flutter_command(CLI::App& cli, CommonOptions& common) {
  auto options = std::make_shared<FlutterOptions>();
  auto* sub =
      cli.add_subcommand("flutter",
                         "Linear flutter analysis: the case's shell linearised about its reference state with "
                         "first-order piston theory at the case's free stream; root locus against lambda = "
                         "rho U^2 a^3/(beta D) or Mach, the critical point (flutter_locus.csv, flutter.json, "
                         "flutter_locus.png), the first in-vacuo modes and the flutter mode (flutter_modes.vtu, "
                         "flutter_modes.png); see docs/flutter.md");
  add_case_options(sub, common);
  add_output_options(sub, common);
  sub->add_option("--parameter", options->parameter,
                  "lambda: sweep lambda at the case's density and Mach; mach: sweep Mach at the case's "
                  "density and pressure")
      ->transform(CLI::CheckedTransformer(std::map<std::string, coupling::FlutterParameter>{
          {"lambda", coupling::FlutterParameter::lambda}, {"mach", coupling::FlutterParameter::mach}}));
  sub->add_option("--range", options->range,
                  "LO HI of the parameter (default: lambda 0..max(1000, 2 lambda_case), Mach "
                  "1.2..max(3, 2 M_case), widened up to 8x until a boundary is found)")
      ->check(finite_number());
  sub->add_option("--points", options->points,
                  "Parameter values of the sweep (the boundary is then "
                  "bisected)")
      ->check(CLI::Range(2, 100000));
  sub->add_option("--modes", options->modes,
                  "In-vacuo modes of the reduced basis, 2 to 400 (flutter is the coalescence of two modes)")
      ->check(CLI::Validator(
          [](const std::string& text) -> std::string {
            int n = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
            if (ec != std::errc() || end != text.data() + text.size() || n < 2 || n > 400)
              return "expected a whole number of modes from 2 to 400 (flutter is the coalescence of two modes; "
                     "the default is 24), got '" +
                     text + "'";
            return {};
          },
          "INT in [2, 400]"));
  sub->add_flag("--direct", options->direct,
                "Solve the full system (every free dof) instead of the modal basis: dense, O(n^3) per "
                "value; for checking the basis on small meshes");
  sub->add_flag("--no-aero-damping", options->no_aerodynamic_damping,
                "Drop the aerodynamic damping (mu/M -> 0: the classical coalescence boundary)");
  sub->add_flag("--json", options->json,
                "Print one JSON object on stdout (lambda_cr, mach_cr, frequency_hz, ...) and nothing else");
  sub->add_option("--aerodynamics", options->aerodynamics,
                  "piston: first-order piston theory on the case's stream; identified: the generalised "
                  "aerodynamic forces of the case's own flow (Euler, or piston theory as a check), identified by "
                  "a forced-motion run of its coupling.identification modes (default 6) into OUTDIR/identification "
                  "(reused when the case's sections are unchanged, or only the shell's and its modes are "
                  "combinations of the identified ones; continued from its checkpoint when stopped), "
                  "fitted by an FIR on [q; q'], solved with Newmark and the case's coupling scheme at the shell "
                  "step; see docs/flutter.md")
      ->transform(CLI::CheckedTransformer(std::map<std::string, FlutterOptions::Aerodynamics>{
          {"piston", FlutterOptions::Aerodynamics::piston}, {"identified", FlutterOptions::Aerodynamics::identified}}));
  sub->add_option("--taps", options->taps,
                  "FIR taps of the identified model (default: twice the flow's memory a / (c (M - 1)) in shell "
                  "steps, plus one; 1 for piston theory)")
      ->check(CLI::Range(1, 100000));
  sub->add_option("--regularisation", options->regularisation,
                  "Tikhonov weight of the identified model's fit, relative to the largest input energy (default 0)")
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--identification-mach", options->identification_mach,
                  "Identify at this Mach number instead of the case's (OUTDIR/identification_mach_M), or at two: "
                  "the models' taps are then interpolated linearly in Mach between them and each is scaled in "
                  "reduced time outside (default: the case's Mach, OUTDIR/identification)")
      ->expected(1, 2)
      ->type_name("M [M2]")
      ->check(CLI::Range(1.0, 100.0));
  return {sub, [&common, options, sub] {
            options->modes_given = sub->count("--modes") > 0;
            return flutter_command(common, *options);
          }};
}

}  // namespace shellflow::app
