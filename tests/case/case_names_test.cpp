// The names of the case file's enumerations (io/case_names.h): every enumerator goes to its
// name through to_string() and back through the parser's table, and the tables' compile-time
// check refuses a table that misses, adds or reorders an enumerator.
#include "shellflow/io/case_names.h"

#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <string>
#include <string_view>

#include "shellflow/io/case.h"
#include "shellflow/io/yaml_reader.h"

namespace shellflow::io {
namespace {

using detail::covers_in_order;
using detail::EnumName;

// covers_in_order() itself: a table that stops short, reorders or names no enumerator.
enum class Three { a, b, c };
static_assert(covers_in_order(std::array<EnumName<Three>, 3>{{{Three::a, "a"}, {Three::b, "b"}, {Three::c, "c"}}}));
static_assert(!covers_in_order(std::array<EnumName<Three>, 2>{{{Three::a, "a"}, {Three::b, "b"}}}));
static_assert(!covers_in_order(std::array<EnumName<Three>, 3>{{{Three::a, "a"}, {Three::c, "c"}, {Three::b, "b"}}}));
static_assert(!covers_in_order(std::array<EnumName<Three>, 3>{{{Three::a, "a"}, {Three::b, "b"}, {Three::c, ""}}}));
static_assert(detail::is_enumerator<Three::c>() && !detail::is_enumerator<static_cast<Three>(3)>());
struct Outer {
  enum class Nested { x };
};
static_assert(detail::is_enumerator<Outer::Nested::x>() && !detail::is_enumerator<static_cast<Outer::Nested>(1)>());

// Parses `name` as the value of a key through the table, as the section readers do.
template <class E, std::size_t N>
E parse(const std::array<EnumName<E>, N>& table, std::string_view name) {
  const YamlNode node = YamlNode::load_string("key: " + std::string(name) + "\n", "cases/names.yaml");
  const E e = detail::read_enum(node, "key", table);
  node.finish();
  return e;
}

// Every entry: its position is its enumerator, the parser reads its name back to it and,
// where the enumeration has a to_string(), that returns the name.
template <class E, std::size_t N>
void expect_round_trip(const std::array<EnumName<E>, N>& table) {
  for (std::size_t i = 0; i < N; ++i) {
    const auto e = static_cast<E>(i);
    SCOPED_TRACE(std::string(table[i].second));
    EXPECT_EQ(table[i].first, e);
    EXPECT_EQ(detail::name_of(table, e), table[i].second);
    if constexpr (requires { to_string(e); }) {
      EXPECT_EQ(to_string(e), table[i].second);
    }
    EXPECT_EQ(parse(table, table[i].second), e);
  }
}

TEST(CaseNames, EveryEnumeratorRoundTripsThroughToStringAndTheParser) {
  expect_round_trip(detail::kMeshFormats);
  expect_round_trip(detail::kTimeFunctionTypes);
  expect_round_trip(detail::kSupportTypes);
  expect_round_trip(detail::kShellLoadTypes);
  expect_round_trip(detail::kShellAnalysisTypes);
  expect_round_trip(detail::kFluidBoundaryTypes);
  expect_round_trip(detail::kFluidSlipWalls);
  expect_round_trip(detail::kMotionMethods);
  expect_round_trip(detail::kMotionWeightings);
  expect_round_trip(detail::kProbeComponents);
  expect_round_trip(detail::kVectorProbeComponents);
  expect_round_trip(detail::kProbeLocations);
  expect_round_trip(detail::kProbeReductions);
  expect_round_trip(detail::kStudyParameters);
  expect_round_trip(detail::kAccelerationTypes);
  expect_round_trip(detail::kFluidModels);
  expect_round_trip(detail::kViscosityLaws);
  expect_round_trip(detail::kFluidAnalysisTypes);
  expect_round_trip(detail::kPathControls);
  expect_round_trip(detail::kTimeSchemes);
  expect_round_trip(detail::kCouplingSchemes);
  expect_round_trip(detail::kPredictors);
  expect_round_trip(detail::kMeshVelocities);
  expect_round_trip(detail::kShellStresses);
}

TEST(CaseNames, ToStringAsCaseFilesWriteThem) {
  EXPECT_EQ(to_string(MeshFormat::msh), "msh");
  EXPECT_EQ(to_string(SupportType::simply_supported_hard), "simply_supported_hard");
  EXPECT_EQ(to_string(ShellLoadType::edge_couple), "edge_couple");
  EXPECT_EQ(to_string(FluidBoundaryType::no_slip_wall), "no_slip_wall");
  EXPECT_EQ(to_string(MotionMethod::direct_idw), "direct_idw");
  EXPECT_EQ(to_string(MotionWeighting::area), "area");
  EXPECT_EQ(to_string(ProbeComponent::scalar), "scalar");
  EXPECT_EQ(to_string(ProbeLocation::group), "group");
  EXPECT_EQ(to_string(ProbeReduce::max), "max");
  EXPECT_EQ(to_string(StudySection::Parameter::dynamic_pressure), "dynamic_pressure");
}

TEST(CaseNames, AVectorProbeNamesEveryComponentButScalar) {
  ASSERT_EQ(detail::kVectorProbeComponents.size() + 1, detail::kProbeComponents.size());
  for (std::size_t i = 0; i < detail::kVectorProbeComponents.size(); ++i) {
    EXPECT_EQ(detail::kVectorProbeComponents[i], detail::kProbeComponents[i]);
  }
  EXPECT_EQ(detail::kProbeComponents.back().first, ProbeComponent::scalar);
}

}  // namespace
}  // namespace shellflow::io
