#include "flutter_identified.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "shellflow/core/error.h"
#include "shellflow/core/json.h"
#include "shellflow/run/run.h"
#include "shellflow/run/run_kinds.h"

namespace shellflow::app {
namespace {

namespace fs = std::filesystem;

/// gaf_record.csv as [q; q'] (samples x 2K) and f (samples x K), with its step.
struct Record {
  Eigen::MatrixXd inputs, forces;
  double dt = 0.0;
};

Record read_record(const fs::path& file, int modes) {
  std::ifstream in(file);
  if (!in) throw Error(fmt::format("{}: cannot open the identification record", file.string()));
  std::string line;
  std::getline(in, line);
  const int columns = 1 + 3 * modes;
  if (std::count(line.begin(), line.end(), ',') + 1 != columns)
    throw Error(fmt::format("{}: expected {} columns (time, q, dq, f of {} modes), got the header '{}'", file.string(),
                            columns, modes, line));
  std::vector<std::vector<double>> rows;
  int number = 1;
  while (std::getline(in, line)) {
    ++number;
    std::vector<double> row;
    std::stringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) {
      char* end = nullptr;
      row.push_back(std::strtod(cell.c_str(), &end));
      if (end == cell.c_str() || *end != '\0' || !std::isfinite(row.back()))
        throw Error(fmt::format("{}:{}: '{}' is not a finite number", file.string(), number, cell));
    }
    if (int(row.size()) != columns)
      throw Error(fmt::format("{}:{}: {} values, expected {}", file.string(), number, row.size(), columns));
    rows.push_back(std::move(row));
  }
  if (rows.size() < 3) throw Error(fmt::format("{}: {} samples; the record is empty", file.string(), rows.size()));
  Record r;
  r.inputs.resize(Eigen::Index(rows.size()), 2 * modes);
  r.forces.resize(Eigen::Index(rows.size()), modes);
  for (std::size_t n = 0; n < rows.size(); ++n)
    for (int j = 0; j < 2 * modes; ++j) {
      r.inputs(Eigen::Index(n), j) = rows[n][std::size_t(1 + j)];
      if (j < modes) r.forces(Eigen::Index(n), j) = rows[n][std::size_t(1 + 2 * modes + j)];
    }
  r.dt = rows[1][0] - rows[0][0];
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

IdentifiedModel identify(const CommonOptions& common, const FlutterOptions& options, int modes,
                         const coupling::FlutterSetting& setting, const fs::path& outdir) {
  // 1. The case as the identification run reads it: its modes, no probes.
  CommonOptions id = common;
  id.output_dir = outdir / "identification";
  id.plot = false;
  id.overrides.push_back(fmt::format("coupling.identification.modes={}", modes));
  io::Case c = read_case(id);
  c.probes.clear();  // the run records the modal forces, not probes
  if (!c.coupling || !c.fluid)
    throw InputError(
        fmt::format("{}: --aerodynamics identified needs a coupled case (coupling and fluid sections) "
                    "whose flow the identification drives",
                    common.case_file.string()));
  const coupling::DiscreteCoupling scheme = discrete_coupling(c);
  // 2. The run, or the earlier one of the same case sections.
  IdentifiedModel m;
  const fs::path folder = *id.output_dir;
  const std::string sections = "\"case_sections\": " + json_string(run::case_sections_digest(c));
  m.reused = fs::exists(folder / "gaf_record.csv") && fs::exists(folder / "gaf.json") &&
             read_text_file(folder / "gaf.json").find(sections) != std::string::npos;
  if (m.reused) {
    spdlog::info("identified aerodynamics: reusing the identification in {} (same case sections)", folder.string());
  } else {
    run::RunOptions ro;
    ro.case_file = common.case_file;
    ro.output_dir = folder;
    ro.plot = false;
    ro.ranks = common.ranks;
    // A run stopped before its record (no gaf.json) continues from its checkpoint; a finished
    // one of other case sections is replaced.
    if (!fs::exists(folder / "gaf.json") && has_checkpoint(folder)) {
      ro.stop.restart = folder;
      spdlog::info("identified aerodynamics: continuing the identification run from its checkpoint in {}",
                   folder.string());
    }
    if (run::run_case(c, ro) != 0) {
      m.stopped = true;
      return m;
    }
  }
  // 3. The fit: FIR taps covering the flow's memory a / (c (M - 1)) twice.
  const Record r = read_record(folder / "gaf_record.csv", modes);
  if (!(std::abs(r.dt - c.time->step) <= 1e-9 * c.time->step))
    throw Error(fmt::format("{}: the record's step {} s is not the case's time.step {} s",
                            (folder / "gaf_record.csv").string(), r.dt, c.time->step));
  const bool piston = c.fluid->model == io::FluidModelType::piston_theory;
  const double sound = std::sqrt(setting.gamma * setting.pressure / setting.density);
  const double memory = setting.length / (sound * std::max(setting.mach - 1.0, 0.1));
  const int taps = options.taps > 0 ? options.taps : piston ? 1 : int(std::ceil(2.0 * memory / r.dt)) + 1;
  if (r.inputs.rows() < 2 * 2 * modes * taps)
    spdlog::warn(
        "identified aerodynamics: {} samples for {} unknowns per force ({} taps of {} inputs): a longer record "
        "(coupling.identification.gap) or fewer --taps determine the model better",
        r.inputs.rows(), 2 * modes * taps, taps, 2 * modes);
  m.fit = coupling::fit_fir(r.inputs, r.forces, r.dt, {taps, options.regularisation});
  const coupling::FlowCondition flow = setting.flow(coupling::FlutterParameter::mach, setting.mach);
  m.aero = std::make_unique<coupling::IdentifiedAerodynamics>(m.fit.model.state_space(), flow, scheme);
  spdlog::info(
      "identified aerodynamics: FIR of {} taps on [q; q'] of {} modes fitted to {} samples, relative "
      "residual {:.3e}; {} coupling",
      taps, modes, m.fit.samples, m.fit.residual,
      scheme == coupling::DiscreteCoupling::staggered ? "staggered (linear predictor)" : "simultaneous");
  m.json = fmt::format(
      "{{\"folder\": {}, \"reused\": {}, \"taps\": {}, \"samples\": {}, \"residual\": {}, \"coupling\": {}, "
      "\"identification_mach\": {}}}",
      json_string(folder.string()), m.reused ? "true" : "false", taps, m.fit.samples, json_number(m.fit.residual),
      json_string(scheme == coupling::DiscreteCoupling::staggered ? "staggered" : "simultaneous"),
      json_number(setting.mach));
  return m;
}

}  // namespace shellflow::app
