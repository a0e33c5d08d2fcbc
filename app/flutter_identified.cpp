#include "flutter_identified.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "shellflow/core/error.h"
#include "shellflow/core/json.h"
#include "shellflow/run/run.h"
#include "shellflow/run/run_kinds.h"
#include "shellflow/shell/shell_model.h"

namespace shellflow::app {
namespace {

namespace fs = std::filesystem;

/// gaf_record.csv as [q; q'] (samples x 2K) and f (samples x K), with its step.
struct Record {
  Eigen::MatrixXd inputs, forces;
  double dt = 0.0;
};

/// The numbers of a CSV file with a header of `columns` names (`what`: what the columns are).
Eigen::MatrixXd read_csv(const fs::path& file, int columns, const std::string& what) {
  std::ifstream in(file);
  if (!in) throw Error(fmt::format("{}: cannot open the identification's file", file.string()));
  std::string line;
  std::getline(in, line);
  if (std::count(line.begin(), line.end(), ',') + 1 != columns)
    throw Error(fmt::format("{}: expected {} columns ({}), got the header '{}'", file.string(), columns, what, line));
  std::vector<double> values;
  int number = 1;
  while (std::getline(in, line)) {
    ++number;
    std::stringstream cells(line);
    std::string cell;
    int count = 0;
    while (std::getline(cells, cell, ',')) {
      char* end = nullptr;
      values.push_back(std::strtod(cell.c_str(), &end));
      ++count;
      if (end == cell.c_str() || *end != '\0' || !std::isfinite(values.back()))
        throw Error(fmt::format("{}:{}: '{}' is not a finite number", file.string(), number, cell));
    }
    if (count != columns)
      throw Error(fmt::format("{}:{}: {} values, expected {}", file.string(), number, count, columns));
  }
  return Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      values.data(), Eigen::Index(values.size()) / columns, columns);
}

Record read_record(const fs::path& file, int modes) {
  const Eigen::MatrixXd rows = read_csv(file, 1 + 3 * modes, fmt::format("time, q, dq, f of {} modes", modes));
  if (rows.rows() < 3) throw Error(fmt::format("{}: {} samples; the record is empty", file.string(), rows.rows()));
  Record r;
  r.inputs = rows.middleCols(1, 2 * modes);
  r.forces = rows.rightCols(modes);
  r.dt = rows(1, 0) - rows(0, 0);
  return r;
}

/// The discrete coupling the case's own time runs use: the explicit staggered scheme with
/// the linear predictor, or the loads of the step's end (coupling iterations, monolithic).
coupling::DiscreteCoupling discrete_coupling(const io::Case& c) {
  const io::CouplingSection& k = *c.coupling;
  if (k.scheme == io::CouplingSection::Scheme::monolithic || k.iterations > 1)
    return coupling::DiscreteCoupling::simultaneous;
  if (k.predictor != io::CouplingSection::Predictor::linear)
    throw_at(k.where,
             "--aerodynamics identified models the staggered scheme with coupling.predictor: linear, or the "
             "implicit one (coupling.iterations > 1); use one of them");
  return coupling::DiscreteCoupling::staggered;
}

}  // namespace

namespace {

/// The case's modes in the identified ones: new = old T in least squares on the mid-surface,
/// with the largest relative residual over the modes (infinite when the meshes differ; T
/// empty and 0 when they are the same bits).
struct ModeMap {
  Eigen::MatrixXd T;
  double residual = std::numeric_limits<double>::infinity();
};

/// One identification run at Mach `mach` (the case's or --identification-mach), fitted.
struct Identification {
  coupling::FirFit fit;
  ModeMap modes;                 ///< the case's modes in the identified ones (T empty: the same bits)
  coupling::FlowCondition flow;  ///< the run's free stream
  fs::path folder;
  int taps = 0;
  bool reused = false, stopped = false;
};

/// The run's folder: OUTDIR/identification at the case's Mach, else identification_mach_M.
fs::path identification_folder(const fs::path& outdir, double mach, double case_mach) {
  return outdir / (mach == case_mach ? std::string("identification") : fmt::format("identification_mach_{:g}", mach));
}

/// "name:digest ..." of the case sections the flow reads: all but the shell's (whose change
/// the modes check) and those that change no flow (description, name, output, probes).
std::string flow_sections(const std::string& sections) {
  std::stringstream in(sections);
  std::string item, out;
  while (in >> item) {
    const std::string name = item.substr(0, item.find(':'));
    if (name != "shell" && name != "description" && name != "name" && name != "output" && name != "probes")
      out += item + ' ';
  }
  return out;
}

/// gaf.json's case_sections.
std::string stored_sections(const fs::path& file) {
  const std::string text = read_text_file(file);
  const std::string key = "\"case_sections\": \"";
  const auto at = text.find(key);
  if (at == std::string::npos) return {};
  const auto from = at + key.size();
  return text.substr(from, text.find('"', from) - from);
}

ModeMap map_modes(const fs::path& file, const Eigen::MatrixXd& basis) {
  ModeMap map;
  const Eigen::MatrixXd stored = read_csv(file, 1 + int(basis.cols()), fmt::format("dof, {} modes", basis.cols()));
  if (stored.rows() != basis.rows()) return map;
  // The flow sees the mid-surface (the first three dofs of each node): the wall follows it and
  // the loads act on it. The directors' part scales with the thickness and is left out.
  std::vector<Eigen::Index> rows;
  for (Eigen::Index i = 0; i < basis.rows(); ++i)
    if (i % shell::dofs_per_node < 3) rows.push_back(i);
  const Eigen::MatrixXd old = stored(rows, Eigen::seqN(1, basis.cols())), now = basis(rows, Eigen::all);
  map.residual = 0.0;
  if (old == now) return map;  // the same modes, bit for bit: nothing to carry over
  map.T = old.colPivHouseholderQr().solve(now);
  for (Eigen::Index j = 0; j < now.cols(); ++j)
    map.residual = std::max(map.residual, (old * map.T.col(j) - now.col(j)).norm() / now.col(j).norm());
  return map;
}

/// The largest relative residual of the new modes against the identified ones for which an
/// identification of another shell section is reused.
constexpr double kModeTolerance = 1e-3;

/// Whether the finished identification in `folder` holds for case `c`: of the same case
/// sections, or of another shell section only; and in both cases of modes that span the
/// case's (`map` then carries the model over when they are not the same bits: another
/// thickness, or round-off of another thread count).
bool reusable(const io::Case& c, const coupling::LinearFlutterSystem& linear, const fs::path& folder, ModeMap& map) {
  if (!fs::exists(folder / "gaf_record.csv") || !fs::exists(folder / "gaf.json")) return false;
  const std::string sections = run::case_sections_digest(c), stored = stored_sections(folder / "gaf.json");
  const bool same = stored == sections;
  if (!same && flow_sections(stored) != flow_sections(sections)) return false;
  if (!fs::exists(folder / "gaf_modes.csv")) {
    if (same)
      spdlog::info("identified aerodynamics: reusing the identification in {} (same case sections)", folder.string());
    return same;
  }
  // The flow's model holds for the modes it was identified with, and so for every
  // combination of them.
  map = map_modes(folder / "gaf_modes.csv", linear.basis());
  if (map.residual <= kModeTolerance) {
    spdlog::info("identified aerodynamics: reusing the identification in {} ({}; its modes {})", folder.string(),
                 same ? "same case sections" : "the shell section changed",
                 map.T.size() == 0 ? "are the case's"
                                   : fmt::format("are combinations of the identified ones to {:.2e}", map.residual));
    return true;
  }
  spdlog::info(
      "identified aerodynamics: {} and its modes are not combinations of the identified ones ({}); identifying anew in "
      "{}",
      same ? "the case sections are the same" : "the shell section changed",
      std::isfinite(map.residual)
          ? fmt::format("{:.2g} of a mode outside them, over {:.0e}", map.residual, kModeTolerance)
          : std::string("another shell mesh"),
      folder.string());
  map = ModeMap{};
  return false;
}

/// The identification run of `c` into `folder`: continued from its checkpoint when it stopped
/// before its record; a finished one of other case sections is replaced. False: it stopped.
bool run_identification(const CommonOptions& common, const io::Case& c, const fs::path& folder) {
  run::RunOptions ro;
  ro.case_file = common.case_file;
  ro.output_dir = folder;
  ro.plot = false;
  ro.ranks = common.ranks;
  if (!fs::exists(folder / "gaf.json") && has_checkpoint(folder)) {
    ro.stop.restart = folder;
    spdlog::info("identified aerodynamics: continuing the identification run from its checkpoint in {}",
                 folder.string());
  }
  return run::run_case(c, ro) == 0;
}

/// The FIR fitted to the record of `id.folder`: taps covering the flow's memory
/// a / (c (M - 1)) twice (one for piston theory), carried over to the case's modes.
void fit(Identification& id, const FlutterOptions& options, int modes, const coupling::FlutterSetting& setting,
         const io::Case& c, double mach) {
  const fs::path file = id.folder / "gaf_record.csv";
  const Record r = read_record(file, modes);
  if (!(std::abs(r.dt - c.time->step) <= 1e-9 * c.time->step))
    throw Error(
        fmt::format("{}: the record's step {} s is not the case's time.step {} s", file.string(), r.dt, c.time->step));
  const bool piston = c.fluid->model == io::FluidModelType::piston_theory;
  const double sound = std::sqrt(setting.gamma * setting.pressure / setting.density);
  const double memory = setting.length / (sound * std::max(mach - 1.0, 0.1));
  id.taps = options.taps > 0 ? options.taps : piston ? 1 : int(std::ceil(2.0 * memory / r.dt)) + 1;
  // The default record (pulses 3 memories apart) has about 1.5 samples per unknown or more, and
  // its velocity pulses determine every tap (docs/flutter.md).
  if (2 * r.inputs.rows() < 3 * 2 * modes * id.taps)
    spdlog::warn(
        "identified aerodynamics: {} samples for {} unknowns per force ({} taps of {} inputs): a longer record "
        "(coupling.identification.gap) or fewer --taps determine the model better",
        r.inputs.rows(), 2 * modes * id.taps, id.taps, 2 * modes);
  id.fit = coupling::fit_fir(r.inputs, r.forces, r.dt, {id.taps, options.regularisation});
  const Eigen::MatrixXd& T = id.modes.T;
  if (T.size() > 0)  // the forces on modes old T of the motion old T q: T^T H diag(T, T)
    for (Eigen::MatrixXd& H : id.fit.model.taps) {
      H.leftCols(modes) = T.transpose() * H.leftCols(modes) * T;
      H.rightCols(modes) = T.transpose() * H.rightCols(modes) * T;
    }
  id.flow = setting.flow(coupling::FlutterParameter::mach, mach);
  spdlog::info(
      "identified aerodynamics at Mach {:g}: FIR of {} taps on [q; q'] of {} modes fitted to {} samples, relative "
      "residual {:.3e}",
      mach, id.taps, modes, id.fit.samples, id.fit.residual);
}

/// Runs (or reuses, or continues) the identification of `c` into `folder` and fits it.
Identification identify_at(const CommonOptions& common, const FlutterOptions& options,
                           const coupling::LinearFlutterSystem& linear, const coupling::FlutterSetting& setting,
                           const io::Case& c, const fs::path& folder, double mach) {
  Identification id;
  id.folder = folder;
  id.reused = reusable(c, linear, folder, id.modes);
  if (!id.reused && !run_identification(common, c, folder)) {
    id.stopped = true;
    return id;
  }
  fit(id, options, int(linear.size()), setting, c, mach);
  return id;
}

std::string run_json(const Identification& id) {
  return fmt::format(
      "{{\"folder\": {}, \"mach\": {}, \"reused\": {}, \"taps\": {}, \"samples\": {}, \"residual\": {}, "
      "\"mode_residual\": {}}}",
      json_string(id.folder.string()), json_number(id.flow.mach), id.reused ? "true" : "false", id.taps, id.fit.samples,
      json_number(id.fit.residual), id.modes.T.size() > 0 ? json_number(id.modes.residual) : std::string("null"));
}

}  // namespace

IdentifiedModel identify(const CommonOptions& common, const FlutterOptions& options,
                         const coupling::LinearFlutterSystem& linear, const coupling::FlutterSetting& setting,
                         const fs::path& outdir) {
  const int modes = int(linear.size());
  std::vector<double> machs = options.identification_mach;
  if (machs.empty()) machs = {setting.mach};
  std::sort(machs.begin(), machs.end());
  if (machs.size() > 2 || (machs.size() == 2 && !(machs[0] < machs[1])) || !(machs[0] > 1.0))
    throw Error(fmt::format("--identification-mach {}: give one or two different supersonic Mach numbers",
                            fmt::join(options.identification_mach, " ")));
  IdentifiedModel m;
  std::vector<Identification> runs;
  coupling::DiscreteCoupling scheme{};
  for (const double mach : machs) {
    // The case as the identification run reads it: its modes, its Mach number, no probes.
    CommonOptions id = common;
    id.output_dir = identification_folder(outdir, mach, setting.mach);
    id.plot = false;
    id.overrides.push_back(fmt::format("coupling.identification.modes={}", modes));
    if (mach != setting.mach) id.overrides.push_back(fmt::format("fluid.free_stream.mach={:.17g}", mach));
    io::Case c = read_case(id);
    c.probes.clear();  // the run records the modal forces, not probes
    if (!c.coupling || !c.fluid)
      throw InputError(
          fmt::format("{}: --aerodynamics identified needs a coupled case (coupling and fluid sections) "
                      "whose flow the identification drives",
                      common.case_file.string()));
    scheme = discrete_coupling(c);
    runs.push_back(identify_at(common, options, linear, setting, c, *id.output_dir, mach));
    if (runs.back().stopped) {
      m.stopped = true;
      return m;
    }
  }
  if (runs.size() == 1)
    m.aero = std::make_unique<coupling::IdentifiedAerodynamics>(runs[0].fit.model.state_space(), runs[0].flow, scheme);
  else
    m.aero = std::make_unique<coupling::MachInterpolatedAerodynamics>(runs[0].fit.model, runs[0].flow,
                                                                      runs[1].fit.model, runs[1].flow, scheme);
  spdlog::info(
      "identified aerodynamics: {} coupling{}",
      scheme == coupling::DiscreteCoupling::staggered ? "staggered (linear predictor)" : "simultaneous",
      runs.size() == 2 ? fmt::format(", the taps interpolated in Mach between {:g} and {:g}", machs[0], machs[1]) : "");
  // The summary: the first run's figures at the top level (one identification), the worst
  // of the two (two), each run in `runs`.
  std::string list;
  bool reused = true;
  double residual = 0.0;
  int taps = 0, samples = runs[0].fit.samples;
  for (const Identification& id : runs) {
    list += (list.empty() ? "" : ", ") + run_json(id);
    reused = reused && id.reused;
    residual = std::max(residual, id.fit.residual);
    taps = std::max(taps, id.taps);
    samples = std::min(samples, id.fit.samples);
  }
  m.reused = reused;
  m.json = fmt::format(
      "{{\"folder\": {}, \"reused\": {}, \"taps\": {}, \"samples\": {}, \"residual\": {}, \"coupling\": {}, "
      "\"identification_mach\": {}, \"runs\": [{}]}}",
      json_string(runs[0].folder.string()), reused ? "true" : "false", taps, samples, json_number(residual),
      json_string(scheme == coupling::DiscreteCoupling::staggered ? "staggered" : "simultaneous"),
      runs.size() == 1 ? json_number(machs[0]) : fmt::format("[{}, {}]", json_number(machs[0]), json_number(machs[1])),
      list);
  return m;
}

}  // namespace shellflow::app
