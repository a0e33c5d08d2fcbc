#pragma once
// `shellflow flutter --aerodynamics identified` (docs/flutter.md, "Identified aerodynamics"):
// the case's forced-motion identification run (run/identification_run.cpp), made or reused in
// OUTDIR/identification, and the discrete-time GAF model fitted to its record.
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "shellflow/coupling/discrete_flutter.h"

namespace shellflow::app {

struct IdentifiedModel {
  std::unique_ptr<coupling::IdentifiedAerodynamics> aero;
  coupling::FirFit fit;
  bool reused = false;   ///< an earlier identification of the same case sections
  bool stopped = false;  ///< the identification run stopped with a checkpoint (run again to go on)
  std::string json;      ///< the `identification` object of flutter.json
};

/// Runs (or reuses) the identification of `modes` modes and fits it: FIR taps covering twice
/// the flow's memory a / (c_inf (M - 1)) (one for piston theory), or options.taps. `setting`:
/// the case's (its free stream is the identification's).
IdentifiedModel identify(const CommonOptions& common, const FlutterOptions& options, int modes,
                         const coupling::FlutterSetting& setting, const std::filesystem::path& outdir);

}  // namespace shellflow::app
