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
  std::unique_ptr<coupling::DiscreteAerodynamics> aero;
  bool reused = false;   ///< earlier identifications of the same case sections
  bool stopped = false;  ///< the identification run stopped with a checkpoint (run again to go on)
  std::string json;      ///< the `identification` object of flutter.json
};

/// Runs (or reuses) the identification of the modes of `linear` and fits it: FIR taps covering twice
/// the flow's memory a / (c_inf (M - 1)) (one for piston theory), or options.taps. At the
/// case's Mach number (OUTDIR/identification), or at the one or two of
/// options.identification_mach (OUTDIR/identification_mach_M; two: the taps interpolated in
/// Mach, coupling::MachInterpolatedAerodynamics). `setting`: the case's. An identification whose
/// case differs in its shell section alone (thickness, material, supports) is reused when the
/// case's modes are combinations of its modes (gaf_modes.csv) to 1e-3, and its model carried
/// over to them; otherwise it is made anew.
IdentifiedModel identify(const CommonOptions& common, const FlutterOptions& options,
                         const coupling::LinearFlutterSystem& linear, const coupling::FlutterSetting& setting,
                         const std::filesystem::path& outdir);

}  // namespace shellflow::app
