#pragma once
// Internal to the case reader: the names of the case file's enumerations, one table per
// enumeration that serves both ways. The reader parses a value with read_enum() (through
// YamlNode::enumeration(), whose messages list the names in table order) and to_string()
// returns table[e].second.
//
// Each table lists every enumerator once, in declaration order, beside its name. The
// static_asserts below check that at compile time (covers_in_order): entry i holds
// enumerator i, and there is no enumerator after the last entry, so adding, removing or
// reordering an enumerator without its table stops the build. tests/case/case_names_test.cpp
// round-trips every entry through to_string() and the parser.
#include <array>
#include <cstddef>
#include <string_view>
#include <utility>

#include "shellflow/io/case.h"
#include "shellflow/io/yaml_reader.h"

namespace shellflow::io::detail {

template <class E>
using EnumName = std::pair<E, std::string_view>;

/// Whether V is a named enumerator of its enumeration. GCC and Clang write a template argument
/// that names no enumerator as `(E)N` in __PRETTY_FUNCTION__ (`[with auto V = (ns::E)6]`,
/// `[V = (ns::E)6]`), an enumerator by its name (`[with auto V = ns::E::symmetry]`).
template <auto V>
constexpr bool is_enumerator() {
  constexpr std::string_view signature = __PRETTY_FUNCTION__;
  constexpr std::size_t at = signature.rfind("V = ");
  static_assert(at != std::string_view::npos, "unexpected __PRETTY_FUNCTION__ format");
  return signature[at + 4] != '(';
}

/// True when `table` names exactly the enumerators of E, in order: entry i holds
/// static_cast<E>(i) and static_cast<E>(N) is not an enumerator (the enumerations here take
/// the default values 0, 1, 2, ...).
template <class E, std::size_t N>
constexpr bool covers_in_order(const std::array<EnumName<E>, N>& table) {
  for (std::size_t i = 0; i < N; ++i) {
    if (table[i].first != static_cast<E>(i) || table[i].second.empty()) return false;
  }
  return !is_enumerator<static_cast<E>(N)>();
}

/// The names of `table`, in its order: what YamlNode::enumeration() takes.
template <class E, std::size_t N>
constexpr std::array<std::string_view, N> names_of(const std::array<EnumName<E>, N>& table) {
  std::array<std::string_view, N> names{};
  for (std::size_t i = 0; i < N; ++i) names[i] = table[i].second;
  return names;
}

/// The name of `e` in `table` (a table that covers_in_order).
template <class E, std::size_t N>
constexpr std::string_view name_of(const std::array<EnumName<E>, N>& table, E e) {
  return table[static_cast<std::size_t>(e)].second;
}

/// The value of `key`, one of the names of `table` (YamlNode::enumeration).
template <class E, std::size_t N>
E read_enum(const YamlNode& node, std::string_view key, const std::array<EnumName<E>, N>& table) {
  const std::array<std::string_view, N> names = names_of(table);
  return node.enumeration<E>(key, names);
}
/// Same; `fallback` when the key is absent.
template <class E, std::size_t N>
E read_enum(const YamlNode& node, std::string_view key, const std::array<EnumName<E>, N>& table, E fallback) {
  const std::array<std::string_view, N> names = names_of(table);
  return node.enumeration<E>(key, names, fallback);
}

// ---- the tables -------------------------------------------------------------------------------

inline constexpr std::array<EnumName<MeshFormat>, 2> kMeshFormats = {{
    {MeshFormat::geo, "geo"},
    {MeshFormat::msh, "msh"},
}};
static_assert(covers_in_order(kMeshFormats));

/// The `type` of a time function (docs/case-format.md "Time functions").
enum class TimeFunctionType { constant, ramp, sine, tabulated, step, smooth_step, expression };
inline constexpr std::array<EnumName<TimeFunctionType>, 7> kTimeFunctionTypes = {{
    {TimeFunctionType::constant, "constant"},
    {TimeFunctionType::ramp, "ramp"},
    {TimeFunctionType::sine, "sine"},
    {TimeFunctionType::tabulated, "tabulated"},
    {TimeFunctionType::step, "step"},
    {TimeFunctionType::smooth_step, "smooth_step"},
    {TimeFunctionType::expression, "expression"},
}};
static_assert(covers_in_order(kTimeFunctionTypes));

inline constexpr std::array<EnumName<SupportType>, 6> kSupportTypes = {{
    {SupportType::clamped, "clamped"},
    {SupportType::simply_supported, "simply_supported"},
    {SupportType::symmetry, "symmetry"},
    {SupportType::sliding, "sliding"},
    {SupportType::prescribed, "prescribed"},
    {SupportType::simply_supported_hard, "simply_supported_hard"},
}};
static_assert(covers_in_order(kSupportTypes));

inline constexpr std::array<EnumName<ShellLoadType>, 6> kShellLoadTypes = {{
    {ShellLoadType::line, "line"},
    {ShellLoadType::point, "point"},
    {ShellLoadType::edge_couple, "edge_couple"},
    {ShellLoadType::pressure, "pressure"},
    {ShellLoadType::gravity, "gravity"},
    {ShellLoadType::surface, "surface"},
}};
static_assert(covers_in_order(kShellLoadTypes));

inline constexpr std::array<EnumName<ShellAnalysisType>, 3> kShellAnalysisTypes = {{
    {ShellAnalysisType::static_load, "static"},
    {ShellAnalysisType::dynamic, "dynamic"},
    {ShellAnalysisType::modal, "modal"},
}};
static_assert(covers_in_order(kShellAnalysisTypes));

inline constexpr std::array<EnumName<FluidBoundaryType>, 6> kFluidBoundaryTypes = {{
    {FluidBoundaryType::supersonic_inflow, "supersonic_inflow"},
    {FluidBoundaryType::supersonic_outflow, "supersonic_outflow"},
    {FluidBoundaryType::far_field, "far_field"},
    {FluidBoundaryType::slip_wall, "slip_wall"},
    {FluidBoundaryType::no_slip_wall, "no_slip_wall"},
    {FluidBoundaryType::symmetry, "symmetry"},
}};
static_assert(covers_in_order(kFluidBoundaryTypes));

inline constexpr std::array<EnumName<FluidSlipWalls>, 2> kFluidSlipWalls = {{
    {FluidSlipWalls::weak, "weak"},
    {FluidSlipWalls::strong, "strong"},
}};
static_assert(covers_in_order(kFluidSlipWalls));

inline constexpr std::array<EnumName<MotionMethod>, 3> kMotionMethods = {{
    {MotionMethod::space_mesh, "space_mesh"},
    {MotionMethod::direct_idw, "direct_idw"},
    {MotionMethod::laplace, "laplace"},
}};
static_assert(covers_in_order(kMotionMethods));

inline constexpr std::array<EnumName<MotionWeighting>, 2> kMotionWeightings = {{
    {MotionWeighting::plain, "plain"},
    {MotionWeighting::area, "area"},
}};
static_assert(covers_in_order(kMotionWeightings));

inline constexpr std::array<EnumName<ProbeComponent>, 5> kProbeComponents = {{
    {ProbeComponent::x, "x"},
    {ProbeComponent::y, "y"},
    {ProbeComponent::z, "z"},
    {ProbeComponent::magnitude, "magnitude"},
    {ProbeComponent::scalar, "scalar"},
}};
static_assert(covers_in_order(kProbeComponents));
/// The components a probe of a vector field may name: all but the last, `scalar`.
inline constexpr std::array<EnumName<ProbeComponent>, 4> kVectorProbeComponents = [] {
  std::array<EnumName<ProbeComponent>, 4> table{};
  for (std::size_t i = 0; i < table.size(); ++i) table[i] = kProbeComponents[i];
  return table;
}();
static_assert(kProbeComponents.back().first == ProbeComponent::scalar);

inline constexpr std::array<EnumName<ProbeLocation>, 3> kProbeLocations = {{
    {ProbeLocation::point, "point"},
    {ProbeLocation::node, "node"},
    {ProbeLocation::group, "group"},
}};
static_assert(covers_in_order(kProbeLocations));

inline constexpr std::array<EnumName<ProbeReduce>, 3> kProbeReductions = {{
    {ProbeReduce::mean, "mean"},
    {ProbeReduce::min, "min"},
    {ProbeReduce::max, "max"},
}};
static_assert(covers_in_order(kProbeReductions));

inline constexpr std::array<EnumName<StudySection::Parameter>, 4> kStudyParameters = {{
    {StudySection::Parameter::mach, "mach"},
    {StudySection::Parameter::density, "density"},
    {StudySection::Parameter::dynamic_pressure, "dynamic_pressure"},
    {StudySection::Parameter::thickness, "thickness"},
}};
static_assert(covers_in_order(kStudyParameters));

inline constexpr std::array<EnumName<CouplingSection::Acceleration::Type>, 4> kAccelerationTypes = {{
    {CouplingSection::Acceleration::Type::none, "none"},
    {CouplingSection::Acceleration::Type::constant, "constant"},
    {CouplingSection::Acceleration::Type::aitken, "aitken"},
    {CouplingSection::Acceleration::Type::iqn_ils, "iqn_ils"},
}};
static_assert(covers_in_order(kAccelerationTypes));

inline constexpr std::array<EnumName<FluidModelType>, 2> kFluidModels = {{
    {FluidModelType::euler, "euler"},
    {FluidModelType::piston_theory, "piston_theory"},
}};
static_assert(covers_in_order(kFluidModels));

inline constexpr std::array<EnumName<ViscosityLaw>, 4> kViscosityLaws = {{
    {ViscosityLaw::none, "none"},
    {ViscosityLaw::constant, "constant"},
    {ViscosityLaw::sutherland, "sutherland"},
    {ViscosityLaw::power, "power"},
}};
static_assert(covers_in_order(kViscosityLaws));

inline constexpr std::array<EnumName<FluidAnalysisType>, 2> kFluidAnalysisTypes = {{
    {FluidAnalysisType::transient, "transient"},
    {FluidAnalysisType::steady, "steady"},
}};
static_assert(covers_in_order(kFluidAnalysisTypes));

inline constexpr std::array<EnumName<PathControl>, 3> kPathControls = {{
    {PathControl::load, "load"},
    {PathControl::displacement, "displacement"},
    {PathControl::arc_length, "arc_length"},
}};
static_assert(covers_in_order(kPathControls));

inline constexpr std::array<EnumName<TimeScheme>, 2> kTimeSchemes = {{
    {TimeScheme::newmark, "newmark"},
    {TimeScheme::midpoint, "midpoint"},
}};
static_assert(covers_in_order(kTimeSchemes));

inline constexpr std::array<EnumName<CouplingSection::Scheme>, 2> kCouplingSchemes = {{
    {CouplingSection::Scheme::staggered, "staggered"},
    {CouplingSection::Scheme::monolithic, "monolithic"},
}};
static_assert(covers_in_order(kCouplingSchemes));

inline constexpr std::array<EnumName<CouplingSection::Predictor>, 2> kPredictors = {{
    {CouplingSection::Predictor::none, "none"},
    {CouplingSection::Predictor::linear, "linear"},
}};
static_assert(covers_in_order(kPredictors));

inline constexpr std::array<EnumName<CouplingSection::MeshVelocity>, 2> kMeshVelocities = {{
    {CouplingSection::MeshVelocity::positions, "positions"},
    {CouplingSection::MeshVelocity::interpolated, "interpolated"},
}};
static_assert(covers_in_order(kMeshVelocities));

inline constexpr std::array<EnumName<OutputSection::ShellStress>, 3> kShellStresses = {{
    {OutputSection::ShellStress::cauchy, "cauchy"},
    {OutputSection::ShellStress::second_piola_kirchhoff, "second_piola_kirchhoff"},
    {OutputSection::ShellStress::none, "none"},
}};
static_assert(covers_in_order(kShellStresses));

}  // namespace shellflow::io::detail
