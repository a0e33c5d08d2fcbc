// Case files: a complete case parses to the expected values (defaults applied), and each
// kind of bad input stops with `FILE:LINE: key.path: message`.
#include "shellflow/io/case.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "shellflow/core/error.h"

namespace shellflow::io {
namespace {

const std::string kDataDir = SHELLFLOW_TEST_DATA_DIR;

std::filesystem::path data(std::string_view name) { return kDataDir + "/" + std::string(name); }

// The message read_case() throws for the data file `name` ("" and a failure if none).
std::string case_error(std::string_view name) {
  try {
    read_case(data(name));
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << name << ": no InputError thrown";
  return {};
}

// `FILE:LINE: rest` for the data file `name`.
std::string at(std::string_view name, int line, std::string_view rest) {
  return data(name).string() + ":" + std::to_string(line) + ": " + std::string(rest);
}

TEST(ReadCase, FullCaseParsesWithDefaultsApplied) {
  const Case c = read_case(data("full.yaml"));
  EXPECT_EQ(c.file, data("full.yaml"));
  EXPECT_EQ(c.name, "panel_flutter_coarse");
  EXPECT_EQ(c.description, "Supersonic panel flutter, coarse meshes");

  ASSERT_TRUE(c.meshes.fluid && c.meshes.space && c.meshes.shell);
  EXPECT_EQ(c.meshes.fluid->key, "fluid");
  EXPECT_EQ(c.meshes.fluid->format, MeshFormat::geo);
  EXPECT_EQ(c.meshes.fluid->file, data("fluid_slab.geo").lexically_normal());
  EXPECT_EQ(c.meshes.fluid->as_written, "fluid_slab.geo");
  EXPECT_EQ(c.meshes.fluid->order, 1);  // default for the fluid mesh
  EXPECT_DOUBLE_EQ(c.meshes.fluid->size_factor, 2.0);
  EXPECT_EQ(c.meshes.fluid->where.line, 5);
  EXPECT_EQ(c.meshes.fluid->where.key_path, "meshes.fluid");
  EXPECT_EQ(c.meshes.space->order, 3);  // default for the space mesh
  EXPECT_DOUBLE_EQ(c.meshes.space->size_factor, 1.0);
  EXPECT_EQ(c.meshes.shell->order, 2);
  EXPECT_EQ(c.meshes.find("shell"), &*c.meshes.shell);
  EXPECT_EQ(c.meshes.find("solid"), nullptr);

  ASSERT_TRUE(c.shell.has_value());
  EXPECT_DOUBLE_EQ(c.shell->thickness, 1.35e-3);
  EXPECT_DOUBLE_EQ(c.shell->material.young_modulus, 77.28e9);
  EXPECT_DOUBLE_EQ(c.shell->material.poisson_ratio, 0.33);
  EXPECT_DOUBLE_EQ(c.shell->material.density, 2710.0);
  ASSERT_EQ(c.shell->supports.size(), 2u);
  EXPECT_EQ(c.shell->supports[0].group, "leading_edge");
  EXPECT_EQ(c.shell->supports[0].type, SupportType::clamped);
  EXPECT_EQ(c.shell->supports[1].group, "side");
  EXPECT_EQ(c.shell->supports[1].type, SupportType::sliding);
  EXPECT_EQ(c.shell->supports[1].direction, Vec3(0, 0, 1));  // normalised
  EXPECT_EQ(c.shell->supports[1].where.line, 13);
  EXPECT_EQ(c.shell->supports[1].where.key_path, "shell.supports[1]");

  ASSERT_TRUE(c.fluid.has_value());
  EXPECT_DOUBLE_EQ(c.fluid->gas.gamma, 1.4);            // default
  EXPECT_DOUBLE_EQ(c.fluid->gas.gas_constant, 287.05);  // default
  EXPECT_DOUBLE_EQ(c.fluid->free_stream.density, 0.339);
  EXPECT_DOUBLE_EQ(c.fluid->free_stream.pressure, 28000.0);
  EXPECT_DOUBLE_EQ(c.fluid->free_stream.mach, 2.3);
  EXPECT_EQ(c.fluid->free_stream.direction, Vec3(1, 0, 0));  // normalised
  ASSERT_EQ(c.fluid->boundaries.size(), 3u);
  EXPECT_EQ(c.fluid->boundaries[0].type, FluidBoundaryType::supersonic_inflow);
  EXPECT_EQ(c.fluid->boundaries[1].type, FluidBoundaryType::supersonic_outflow);
  EXPECT_EQ(c.fluid->boundaries[2].group, "panel");
  EXPECT_EQ(c.fluid->boundaries[2].type, FluidBoundaryType::slip_wall);

  ASSERT_EQ(c.probes.size(), 4u);
  const Probe& w = c.probes[0];
  EXPECT_EQ(w.name, "w_075");
  EXPECT_EQ(w.field, "shell.displacement");
  EXPECT_EQ(w.mesh, "shell");
  EXPECT_EQ(w.quantity, "displacement");
  EXPECT_EQ(w.component, ProbeComponent::y);
  EXPECT_EQ(w.location, ProbeLocation::point);
  EXPECT_EQ(w.point, Vec3(0.625, 0.0, 0.0125));
  const Probe& p = c.probes[1];
  EXPECT_EQ(p.component, ProbeComponent::scalar);
  EXPECT_EQ(p.location, ProbeLocation::group);
  EXPECT_EQ(p.group, "panel");
  EXPECT_EQ(p.reduce, ProbeReduce::max);
  const Probe& v = c.probes[2];
  EXPECT_EQ(v.mesh, "space");
  EXPECT_EQ(v.component, ProbeComponent::magnitude);  // default for vectors
  EXPECT_EQ(v.location, ProbeLocation::node);
  EXPECT_EQ(v.node, 3);
  EXPECT_EQ(c.probes[3].reduce, ProbeReduce::mean);  // default
  EXPECT_EQ(c.probes[3].where.line, 26);

  EXPECT_EQ(c.output.directory, std::filesystem::path("out/panel_flutter_coarse"));
  EXPECT_EQ(c.output.every, 10);

  // Every group, with the mesh it belongs to and where it was named, in file order.
  const std::vector<std::pair<std::string, std::string>> groups = {
      {"leading_edge", "shell"}, {"side", "shell"},  {"inflow", "fluid"},       {"outflow", "fluid"},
      {"panel", "fluid"},        {"panel", "fluid"}, {"panel_surface", "shell"}};
  ASSERT_EQ(c.group_references.size(), groups.size());
  for (std::size_t i = 0; i < groups.size(); ++i) {
    EXPECT_EQ(c.group_references[i].group, groups[i].first) << i;
    EXPECT_EQ(c.group_references[i].mesh, groups[i].second) << i;
  }
  EXPECT_EQ(c.group_references[0].where.message("m"), at("full.yaml", 12, "shell.supports[0].group: m"));
  EXPECT_EQ(c.group_references[5].where.key_path, "probes[1].group");
}

TEST(ReadCase, MinimalCaseNeedsOnlyANameAndOneMesh) {
  const Case c = read_case(data("minimal.yaml"));
  EXPECT_EQ(c.name, "mesh_only");
  ASSERT_TRUE(c.meshes.space.has_value());
  EXPECT_FALSE(c.meshes.fluid || c.meshes.shell || c.shell || c.fluid);
  EXPECT_EQ(c.meshes.space->format, MeshFormat::msh);
  EXPECT_TRUE(c.probes.empty());
  EXPECT_EQ(c.output.directory, std::filesystem::path("out/mesh_only"));
  EXPECT_EQ(c.output.every, 1);
}

TEST(ReadCase, OutputDirectoryAndDescriptionAsGiven) {
  const Case c = read_case_string(
      "name: t\n"
      "description: 'free text: with a colon'\n"
      "meshes: { fluid: { msh: panel_strip.msh } }\n"
      "output: { directory: results/run-1 }\n",
      data("inline.yaml"));
  EXPECT_EQ(c.description, "free text: with a colon");
  EXPECT_EQ(c.meshes.fluid->order, 0);  // a .msh is used as it is
  EXPECT_EQ(c.output.directory, std::filesystem::path("results/run-1"));
  EXPECT_EQ(c.output.every, 1);
}

// The complete example of docs/case-format.md parses (its mesh files exist in data/).
TEST(ReadCase, DocumentationExampleParses) {
  std::ifstream in(std::string(SHELLFLOW_SOURCE_DIR) + "/docs/case-format.md");
  ASSERT_TRUE(in) << "docs/case-format.md not found";
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string doc = buffer.str();
  const auto section = doc.find("## Complete example");
  ASSERT_NE(section, std::string::npos);
  const auto begin = doc.find("```yaml\n", section);
  ASSERT_NE(begin, std::string::npos);
  const auto end = doc.find("```", begin + 8);
  ASSERT_NE(end, std::string::npos);
  const Case c = read_case_string(doc.substr(begin + 8, end - begin - 8), data("doc_example.yaml"));
  EXPECT_EQ(c.name, "panel_flutter_coarse");
  ASSERT_TRUE(c.shell && c.fluid);
  EXPECT_EQ(c.shell->supports.size(), 3u);
  EXPECT_EQ(c.probes.size(), 3u);
  EXPECT_EQ(c.output.every, 10);
}

TEST(ReadCase, MisspelledTopLevelKeyIsUnknownWithSuggestion) {
  EXPECT_EQ(case_error("unknown_key_top.yaml"),
            at("unknown_key_top.yaml", 4, "outptu: unknown key; did you mean 'output'?"));
}

TEST(ReadCase, MisspelledNestedKeyIsUnknownWithSuggestion) {
  EXPECT_EQ(case_error("unknown_key_nested.yaml"),
            at("unknown_key_nested.yaml", 5, "meshes.fluid.ordr: unknown key; did you mean 'order'?"));
}

TEST(ReadCase, MisspelledRequiredKeyIsReportedWhereItIs) {
  EXPECT_EQ(case_error("misspelled_required.yaml"),
            at("misspelled_required.yaml", 5, "shell.thicknes: unknown key; did you mean 'thickness'?"));
}

TEST(ReadCase, WrongTypeNamesTheKeyAndTheExpectedType) {
  EXPECT_EQ(case_error("wrong_type_number.yaml"),
            at("wrong_type_number.yaml", 5, "shell.thickness: expected a number, got 'abc'"));
  EXPECT_EQ(case_error("wrong_type_list.yaml"),
            at("wrong_type_list.yaml", 7, "shell.supports: expected a list, got a map"));
}

TEST(ReadCase, MissingRequiredKeyNamesTheMapAndTheKey) {
  EXPECT_EQ(case_error("missing_required.yaml"),
            at("missing_required.yaml", 3, "meshes.space: missing required key 'geo' or 'msh'"));
}

TEST(ReadCase, NegativeThicknessIsOutOfRange) {
  EXPECT_EQ(case_error("negative_thickness.yaml"),
            at("negative_thickness.yaml", 6, "shell.thickness: must be > 0 m, got -0.001"));
}

TEST(ReadCase, PoissonRatioOutOfRange) {
  EXPECT_EQ(case_error("poisson_out_of_range.yaml"),
            at("poisson_out_of_range.yaml", 8, "shell.material.poisson_ratio: must be in (-1, 0.5), got 0.6"));
}

TEST(ReadCase, BothGeoAndMshIsAnError) {
  EXPECT_EQ(case_error("geo_and_msh.yaml"),
            at("geo_and_msh.yaml", 4, "meshes.shell: both 'geo' and 'msh' given; expected exactly one of them"));
}

TEST(ReadCase, MissingMeshFileNamesTheKeyAndThePathLookedFor) {
  EXPECT_EQ(case_error("missing_mesh_file.yaml"),
            at("missing_mesh_file.yaml", 4,
               "meshes.shell.geo: file not found: 'panel_stip.geo' (looked for '" +
                   data("panel_stip.geo").lexically_normal().string() +
                   "'); paths are relative to the case file's directory"));
}

TEST(ReadCase, DuplicateProbeNamesAreErrors) {
  EXPECT_EQ(case_error("duplicate_probe.yaml"),
            at("duplicate_probe.yaml", 7,
               "probes[2].name: duplicate probe name 'w_mid' (first used at line 5); expected "
               "unique names"));
}

TEST(ReadCase, YamlSyntaxErrorHasFileAndLine) {
  const std::string message = case_error("syntax_error.yaml");
  const std::string prefix = data("syntax_error.yaml").string() + ":";
  ASSERT_EQ(message.rfind(prefix, 0), 0u) << message;
  // yaml-cpp notices the unclosed `{` of line 3 on line 4 or 5; either names the place.
  const int line = std::stoi(message.substr(prefix.size()));
  EXPECT_GE(line, 3) << message;
  EXPECT_LE(line, 5) << message;
  EXPECT_NE(message.find(": YAML syntax error: "), std::string::npos) << message;
}

TEST(ReadCase, MissingCaseFile) {
  EXPECT_EQ(case_error("no_such_case.yaml"),
            data("no_such_case.yaml").string() + ": cannot open case file (no such file)");
}

TEST(CheckPhysicalGroups, MissingGroupIsReportedAtItsLine) {
  const Case c = read_case(data("group_typo.yaml"));
  int calls = 0;
  const auto groups = [&](std::string_view mesh) {
    ++calls;
    EXPECT_EQ(mesh, "shell");
    return std::vector<std::string>{"leading_edge", "trailing_edge", "panel"};
  };
  try {
    check_physical_groups(c, groups);
    ADD_FAILURE() << "no InputError thrown";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), at("group_typo.yaml", 10,
                                        "shell.supports[2].group: physical group 'leadng_edge' not found in mesh "
                                        "'shell' (panel_strip.geo); did you mean 'leading_edge'? available: "
                                        "leading_edge, trailing_edge, panel"));
  }
  EXPECT_EQ(calls, 1);  // asked once per mesh
}

TEST(CheckPhysicalGroups, PassesWhenEveryGroupExists) {
  const Case c = read_case(data("full.yaml"));
  const std::map<std::string, std::vector<std::string>, std::less<>> groups = {
      {"shell", {"leading_edge", "side", "panel_surface"}}, {"fluid", {"inflow", "outflow", "panel"}}};
  EXPECT_NO_THROW(check_physical_groups(c, [&](std::string_view mesh) { return groups.find(mesh)->second; }));
  EXPECT_THROW(check_physical_groups(c, [](std::string_view) { return std::vector<std::string>{}; }), InputError);
}

// Smaller error classes, from text (mesh paths resolve against the data directory).
std::string text_error(const std::string& text) {
  try {
    read_case_string(text, data("inline.yaml"));
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError thrown for:\n" << text;
  return {};
}

const std::string kShellHead =
    "name: t\n"
    "meshes: { shell: { geo: panel_strip.geo } }\n";

TEST(ReadCaseErrors, NamesMustBeFileSafe) {
  EXPECT_EQ(text_error("name: my case\nmeshes: { shell: { geo: panel_strip.geo } }\n"),
            at("inline.yaml", 1, "name: must contain only letters, digits, '_', '.' and '-', got 'my case'"));
}

TEST(ReadCaseErrors, MeshesNeedAtLeastOneMesh) {
  EXPECT_EQ(text_error("name: t\nmeshes: {}\n"),
            at("inline.yaml", 2, "meshes: no mesh given; expected at least one of 'fluid', 'space', 'shell'"));
  EXPECT_EQ(text_error("name: t\nmeshes:\n  fliud: { geo: fluid_slab.geo }\n"),
            at("inline.yaml", 3, "meshes.fliud: unknown key; did you mean 'fluid'?"));
}

TEST(ReadCaseErrors, MeshOrderAndExtension) {
  EXPECT_EQ(text_error("name: t\nmeshes: { shell: { geo: panel_strip.geo, order: 4 } }\n"),
            at("inline.yaml", 2, "meshes.shell.order: must be in [1, 3], got 4"));
  EXPECT_EQ(text_error("name: t\nmeshes: { shell: { geo: panel_strip.msh } }\n"),
            at("inline.yaml", 2, "meshes.shell.geo: expected a Gmsh .geo file, got 'panel_strip.msh'"));
  EXPECT_EQ(text_error("name: t\nmeshes: { shell: { msh: panel_strip.msh, order: 2 } }\n"),
            at("inline.yaml", 2,
               "meshes.shell.order: applies only to meshes given by 'geo'; a .msh file is used "
               "as it is"));
}

TEST(ReadCaseErrors, SectionsNeedTheirMesh) {
  EXPECT_EQ(text_error(kShellHead + "fluid:\n  free_stream: { density: 1, pressure: 1, mach: 2 }\n"),
            at("inline.yaml", 3, "fluid: needs a fluid mesh; expected 'meshes.fluid' with 'geo' or 'msh'"));
}

TEST(ReadCaseErrors, SupportTypesAndSlidingDirection) {
  const std::string shell = kShellHead +
                            "shell:\n"
                            "  thickness: 1e-3\n"
                            "  material: { young_modulus: 1e9, poisson_ratio: 0.3, density: 1 }\n"
                            "  supports:\n";
  EXPECT_EQ(text_error(shell + "    - { group: a, type: clampd }\n"),
            at("inline.yaml", 7,
               "shell.supports[0].type: unknown value 'clampd'; did you mean 'clamped'? (one of: "
               "clamped, simply_supported, symmetry, sliding, prescribed, simply_supported_hard)"));
  EXPECT_EQ(text_error(shell + "    - { group: a, type: sliding }\n"),
            at("inline.yaml", 7, "shell.supports[0]: missing required key 'direction'"));
  EXPECT_EQ(text_error(shell + "    - { group: a, type: sliding, direction: [0, 0, 0] }\n"),
            at("inline.yaml", 7, "shell.supports[0].direction: must be a non-zero vector [x, y, z], got [0, 0, 0]"));
  EXPECT_EQ(text_error(shell + "    - { group: a, type: clamped, direction: [1, 0, 0] }\n"),
            at("inline.yaml", 7, "shell.supports[0].direction: applies only to supports of type 'sliding'"));
}

TEST(ReadCaseErrors, FluidValues) {
  const std::string head =
      "name: t\n"
      "meshes: { fluid: { geo: fluid_slab.geo } }\n"
      "fluid:\n";
  EXPECT_EQ(text_error(head + "  gas: { gamma: 1.0 }\n"
                              "  free_stream: { density: 1, pressure: 1, mach: 2 }\n"),
            at("inline.yaml", 4, "fluid.gas.gamma: must be > 1, got 1.0"));
  EXPECT_EQ(text_error(head + "  free_stream: { density: 1, pressure: 0, mach: 2 }\n"),
            at("inline.yaml", 4, "fluid.free_stream.pressure: must be > 0 Pa, got 0"));
  EXPECT_EQ(text_error(head + "  free_stream: { density: 1, pressure: 1, mach: -2 }\n"),
            at("inline.yaml", 4, "fluid.free_stream.mach: must be >= 0, got -2"));
  EXPECT_EQ(text_error(head + "  free_stream: { density: 1, pressure: 1, mach: 2 }\n"
                              "  boundaries:\n"
                              "    - { group: a, type: slip_wall }\n"
                              "    - { group: a, type: far_field }\n"),
            at("inline.yaml", 7,
               "fluid.boundaries[1].group: group 'a' already has a boundary condition (line 6); "
               "expected one condition per group"));
}

TEST(ReadCaseErrors, ProbeFieldsAndLocations) {
  const std::string head = kShellHead + "probes:\n";
  EXPECT_EQ(text_error(head + "  - { name: a, field: shell.displacment, point: [0, 0, 0] }\n"),
            at("inline.yaml", 4,
               "probes[0].field: unknown field 'shell.displacment'; did you mean "
               "'shell.displacement'? (one of: shell.displacement, shell.velocity, "
               "shell.acceleration, shell.position)"));
  EXPECT_EQ(text_error(head + "  - { name: a, field: pressure, point: [0, 0, 0] }\n"),
            at("inline.yaml", 4,
               "probes[0].field: expected 'MESH.QUANTITY' with MESH one of fluid, space, shell, "
               "got 'pressure'"));
  EXPECT_EQ(text_error(head + "  - { name: a, field: fluid.pressure, point: [0, 0, 0] }\n"),
            at("inline.yaml", 4, "probes[0].field: the case has no fluid mesh; expected 'meshes.fluid'"));
  EXPECT_EQ(text_error(head + "  - { name: a, field: shell.velocity }\n"),
            at("inline.yaml", 4, "probes[0]: missing required key 'point', 'node' or 'group'"));
  EXPECT_EQ(text_error(head + "  - { name: a, field: shell.velocity, node: 1, group: g }\n"),
            at("inline.yaml", 4, "probes[0]: give only one of 'point', 'node', 'group'"));
  EXPECT_EQ(text_error(head + "  - { name: a, field: shell.velocity, node: -1 }\n"),
            at("inline.yaml", 4, "probes[0].node: must be >= 0, got -1"));
  EXPECT_EQ(text_error(head + "  - { name: a, field: shell.velocity, node: 1, reduce: max }\n"),
            at("inline.yaml", 4, "probes[0].reduce: applies only to probes on a 'group'"));
  EXPECT_EQ(text_error(head + "  - { name: time, field: shell.velocity, node: 1 }\n"),
            at("inline.yaml", 4,
               "probes[0].name: 'time' is reserved for the time column of probes.csv; expected "
               "another name"));
  EXPECT_EQ(text_error(head + "  - { name: a, field: shell.velocity, component: w, node: 1 }\n"),
            at("inline.yaml", 4, "probes[0].component: unknown value 'w'; expected one of: x, y, z, magnitude"));
}

TEST(ReadCaseErrors, OutputEvery) {
  EXPECT_EQ(text_error(kShellHead + "output: { every: 0 }\n"),
            at("inline.yaml", 3, "output.every: must be >= 1, got 0"));
  EXPECT_EQ(text_error(kShellHead + "output: { every: 2.5 }\n"),
            at("inline.yaml", 3, "output.every: expected an integer, got '2.5'"));
}

}  // namespace
}  // namespace shellflow::io

namespace shellflow::io {
namespace {

const std::string kMotionHead =
    "name: t\n"
    "meshes: { fluid: { geo: fluid_slab.geo }, space: { geo: space_mesh.geo } }\n";
// The smallest boundary motion of a `motion` section.
const std::string kPanelMode =
    "  prescribed: { type: panel_modes, leading_edge: [0, 0, 0], length: 0.5,\n"
    "                modes: [{ amplitude: { type: constant, value: 0.01 } }] }\n";

TEST(ReadCase, MotionAndTimeSectionsParseWithDefaults) {
  const Case c =
      read_case_string(kMotionHead +
                           "motion:\n"
                           "  interface_groups: [panel]\n"
                           "  fixed_groups: [inflow, wall]\n"
                           "  sliding_groups: [symmetry]\n"
                           "  prescribed:\n"
                           "    type: panel_modes\n"
                           "    leading_edge: [0.25, 0, 0]\n"
                           "    length: 0.5\n"
                           "    normal: [0, 2, 0]\n"
                           "    modes:\n"
                           "      - { amplitude: { type: ramp, value: 0.1, duration: 2 } }\n"
                           "      - { wave_number: 2, amplitude: { type: tabulated, times: [0, 1], values: [0, "
                           "0.04] } }\n"
                           "time: { end: 1, step: 0.01 }\n",
                       data("inline.yaml"));
  ASSERT_TRUE(c.motion && c.time);
  EXPECT_EQ(c.motion->method, MotionMethod::space_mesh);
  EXPECT_EQ(c.motion->weighting, MotionWeighting::plain);
  EXPECT_EQ(c.motion->interface_exponent, 4.0);
  EXPECT_EQ(c.motion->fixed_groups, (std::vector<std::string>{"inflow", "wall"}));
  ASSERT_TRUE(c.motion->prescribed);
  const auto& p = *c.motion->prescribed;
  EXPECT_EQ(p.normal, Vec3::UnitY());  // normalised
  EXPECT_EQ(p.direction, Vec3::UnitX());
  ASSERT_EQ(p.modes.size(), 2u);
  EXPECT_EQ(p.modes[0].wave_number, 1);
  EXPECT_DOUBLE_EQ(p.modes[0].amplitude.value(1.0), 0.05);
  EXPECT_DOUBLE_EQ(p.modes[0].amplitude.derivative(1.0), 0.05);
  EXPECT_DOUBLE_EQ(p.modes[1].amplitude.value(0.5), 0.02);
  EXPECT_EQ(c.time->step, 0.01);
  // Every group is referenced on both the fluid and the space mesh, at its own line.
  int space_refs = 0;
  for (const auto& ref : c.group_references) space_refs += ref.mesh == "space";
  EXPECT_EQ(space_refs, 4);
}

TEST(ReadCaseErrors, MotionSection) {
  EXPECT_EQ(text_error(kMotionHead + "motion: { interface_groups: [panel] }\n"),
            at("inline.yaml", 3, "motion: a mesh-motion run needs a 'time' section (end, step)"));
  EXPECT_EQ(text_error(kMotionHead + "motion: { interface_groups: [] }\n"),
            at("inline.yaml", 3, "motion.interface_groups: expected a list of the moving boundary's physical groups"));
  EXPECT_EQ(text_error(kMotionHead + "motion: { method: laplac, interface_groups: [panel] }\n"),
            at("inline.yaml", 3,
               "motion.method: unknown value 'laplac'; did you mean 'laplace'? (one of: "
               "space_mesh, direct_idw, laplace)"));
  EXPECT_EQ(text_error("name: t\nmeshes: { fluid: { geo: fluid_slab.geo } }\n"
                       "motion: { interface_groups: [panel] }\n"),
            at("inline.yaml", 3, "motion: needs a space mesh; expected 'meshes.space' with 'geo' or 'msh'"));
  EXPECT_EQ(text_error(kMotionHead + "motion:\n  interface_groups: [panel]\n  prescribed:\n    type: panel_modes\n"
                                     "    leading_edge: [0, 0, 0]\n    length: 0.5\n    modes:\n"
                                     "      - { amplitude: { type: ramp, value: 1, duration: -1 } }\n"),
            at("inline.yaml", 10, "motion.prescribed.modes[0].amplitude.duration: must be > 0 s, got -1"));
  EXPECT_EQ(text_error(kMotionHead + "time: { end: 1, step: 2 }\n"),
            at("inline.yaml", 3, "time.step: must not exceed time.end = 1 s"));
  // What `run` refuses before it starts, `check` refuses: no boundary motion, no coupling.
  EXPECT_EQ(text_error(kMotionHead + "motion:\n  interface_groups: [panel]\ntime: { end: 1, step: 0.1 }\n"),
            at("inline.yaml", 3,
               "motion: a mesh-motion run without a 'coupling' section needs 'prescribed' (the boundary "
               "motion); add it, or a 'coupling' section to let the shell drive it"));
  EXPECT_NO_THROW(read_case_string(
      kMotionHead + "motion:\n  interface_groups: [panel]\n" + kPanelMode + "time: { end: 1, step: 0.1 }\n",
      data("inline.yaml")));
}

TEST(CheckPhysicalGroups, MotionGroupsAreCheckedOnTheSpaceMeshToo) {
  const Case c = read_case_string(
      kMotionHead + "motion:\n  interface_groups: [panel]\n" + kPanelMode + "time: { end: 1, step: 0.1 }\n",
      data("inline.yaml"));
  try {
    check_physical_groups(c, [](std::string_view mesh) {
      return mesh == "fluid" ? std::vector<std::string>{"panel"} : std::vector<std::string>{"wall"};
    });
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("inline.yaml:4: motion.interface_groups[0]: physical "
                                         "group 'panel' not found in mesh 'space'"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace shellflow::io

namespace shellflow::io {
namespace {

const std::string kShellCase =
    "name: t\n"
    "meshes: { shell: { geo: panel_strip.geo } }\n"
    "shell:\n"
    "  thickness: 0.1\n"
    "  material: { young_modulus: 1e6, poisson_ratio: 0, density: 1 }\n";

TEST(ReadCase, ShellLoadsAndAnalysisParse) {
  const Case c =
      read_case_string(kShellCase +
                           "  supports:\n"
                           "    - { group: a, type: symmetry, normal: [0, 0, 2] }\n"
                           "    - { group: b, type: sliding, direction: [1, 0, 0], clamp_director: false }\n"
                           "  loads:\n"
                           "    - { type: line, group: tip, force_per_length: [0, 0, 4] }\n"
                           "    - { type: point, point: [1, 0, 0], force: [0, 1, 0] }\n"
                           "    - { type: edge_couple, group: tip, axis: [0, -2, 0], moment_per_length: 5 }\n"
                           "    - { type: pressure, pressure: 100 }\n"
                           "    - { type: gravity, acceleration: [0, 0, -9.81] }\n"
                           "  analysis: { type: dynamic, mass_damping: 0.5,\n"
                           "              load_function: { type: ramp, value: 2, duration: 0.1 } }\n"
                           "time: { end: 1, step: 0.1 }\n",
                       data("inline.yaml"));
  ASSERT_TRUE(c.shell && c.shell->analysis);
  const auto& s = *c.shell;
  EXPECT_EQ(s.supports[0].normal, Vec3::UnitZ());
  EXPECT_FALSE(s.supports[1].clamp_director);
  ASSERT_EQ(s.loads.size(), 5u);
  EXPECT_EQ(s.loads[0].type, ShellLoadType::line);
  EXPECT_EQ(s.loads[0].group, "tip");
  EXPECT_EQ(s.loads[1].point, Vec3::UnitX());
  EXPECT_EQ(s.loads[2].vector, -Vec3::UnitY());
  EXPECT_EQ(s.loads[2].value, 5.0);
  EXPECT_TRUE(s.loads[3].group.empty());
  EXPECT_EQ(s.loads[4].vector, Vec3(0, 0, -9.81));
  EXPECT_EQ(s.analysis->type, ShellAnalysisType::dynamic);
  EXPECT_EQ(s.analysis->mass_damping, 0.5);
  EXPECT_DOUBLE_EQ(s.analysis->load_function.value(0.05), 1.0);
  EXPECT_FALSE(s.analysis->modified_newton);
}

TEST(ReadCase, PrescribedAndHardSupportsSurfaceTractionAndStressOutput) {
  const Case c =
      read_case_string(kShellCase +
                           "  supports:\n"
                           "    - { group: a, type: prescribed, displacement: [0, 0, 0.01],\n"
                           "        history: { type: ramp, value: 1, duration: 0.5 },\n"
                           "        rotation_axis: [0, 3, 0], rotation_angle: { type: constant, value: 0.2 } }\n"
                           "    - { group: b, type: prescribed, displacement: [1, 0, 0] }\n"
                           "    - { group: c, type: simply_supported_hard }\n"
                           "    - { group: d, type: sliding, direction: [1, 1, 0] }\n"
                           "  loads:\n"
                           "    - { type: surface, traction: [0, 0, -50] }\n"
                           "    - { type: surface, group: top, traction: [1, 0, 0] }\n"
                           "output: { shell_stress: second_piola_kirchhoff }\n",
                       data("inline.yaml"));
  ASSERT_TRUE(c.shell);
  const auto& s = *c.shell;
  ASSERT_EQ(s.supports.size(), 4u);
  EXPECT_EQ(s.supports[0].type, SupportType::prescribed);
  EXPECT_EQ(s.supports[0].displacement, Vec3(0, 0, 0.01));
  ASSERT_TRUE(s.supports[0].displacement_history);
  EXPECT_DOUBLE_EQ(s.supports[0].displacement_history->value(0.25), 0.5);
  EXPECT_EQ(s.supports[0].rotation_axis, Vec3::UnitY());
  EXPECT_EQ(s.supports[0].rotation_angle.value(3.0), 0.2);
  EXPECT_FALSE(s.supports[1].displacement_history);  // follows the load factor
  EXPECT_EQ(s.supports[1].rotation_axis, Vec3::Zero());
  EXPECT_EQ(s.supports[2].type, SupportType::simply_supported_hard);
  EXPECT_NEAR(s.supports[3].direction.x(), std::sqrt(0.5), 1e-15);
  ASSERT_EQ(s.loads.size(), 2u);
  EXPECT_EQ(s.loads[0].type, ShellLoadType::surface);
  EXPECT_TRUE(s.loads[0].group.empty());
  EXPECT_EQ(s.loads[0].vector, Vec3(0, 0, -50));
  EXPECT_EQ(s.loads[1].group, "top");
  EXPECT_EQ(c.output.shell_stress, OutputSection::ShellStress::second_piola_kirchhoff);
  EXPECT_EQ(read_case_string(kShellCase, data("inline.yaml")).output.shell_stress, OutputSection::ShellStress::cauchy);
}

TEST(ReadCaseErrors, PrescribedSupportKeys) {
  EXPECT_EQ(text_error(kShellCase + "  supports: [ { group: a, type: prescribed } ]\n"),
            at("inline.yaml", 6,
               "shell.supports[0]: a prescribed support needs 'displacement' "
               "[x, y, z] and/or 'rotation_axis' with 'rotation_angle'"));
  EXPECT_EQ(text_error(kShellCase + "  supports: [ { group: a, type: clamped, displacement: [0, 0, 1] } ]\n"),
            at("inline.yaml", 6, "shell.supports[0].displacement: applies only to supports of type 'prescribed'"));
  EXPECT_EQ(text_error(kShellCase + "  supports: [ { group: a, type: prescribed, rotation_axis: [1, 0, 0] } ]\n"),
            at("inline.yaml", 6, "shell.supports[0]: missing required key 'rotation_angle'"));
  EXPECT_EQ(text_error(kShellCase + "  supports: [ { group: a, type: prescribed, displacement: [0, 0, 1],\n"
                                    "                rotation_angle: { type: constant, value: 1 } } ]\n"),
            at("inline.yaml", 7, "shell.supports[0].rotation_angle: needs 'rotation_axis' [x, y, z] beside it"));
  EXPECT_EQ(text_error(kShellCase + "  loads: [ { type: surface } ]\n"),
            at("inline.yaml", 6, "shell.loads[0]: missing required key 'traction'"));
}

TEST(ReadCaseErrors, ShellSupportsLoadsAndAnalysis) {
  EXPECT_EQ(text_error(kShellCase + "  supports: [ { group: a, type: symmetry } ]\n"),
            at("inline.yaml", 6, "shell.supports[0]: missing required key 'normal'"));
  EXPECT_EQ(text_error(kShellCase + "  loads: [ { type: line, group: a } ]\n"),
            at("inline.yaml", 6, "shell.loads[0]: missing required key 'force_per_length'"));
  EXPECT_EQ(text_error(kShellCase + "  analysis: { type: dynamic }\n"),
            at("inline.yaml", 6,
               "shell.analysis: a dynamic analysis needs a 'time' section "
               "(end, step)"));
  EXPECT_EQ(text_error(kShellCase + "  analysis: { type: static, steps: 0 }\n"),
            at("inline.yaml", 6, "shell.analysis.steps: must be >= 1, got 0"));
}

}  // namespace
}  // namespace shellflow::io

namespace shellflow::io {
namespace {

const std::string kFluidCase =
    "name: t\n"
    "meshes: { fluid: { geo: fluid_slab.geo } }\n"
    "fluid:\n"
    "  free_stream: { density: 1, pressure: 1, mach: 0 }\n";

TEST(ReadCase, FluidAnalysisParses) {
  const Case c = read_case_string(kFluidCase +
                                      "  analysis:\n"
                                      "    type: transient\n"
                                      "    cfl: 1.0\n"
                                      "    q_dif: 0.5\n"
                                      "    riemann: { position: 0.5, left: { density: 1, pressure: 1 },\n"
                                      "               right: { density: 0.125, pressure: 0.1, velocity: [1, 0, 0] } }\n"
                                      "time: { end: 0.2 }\n",
                                  data("inline.yaml"));
  ASSERT_TRUE(c.fluid && c.fluid->analysis && c.fluid->analysis->riemann);
  const auto& a = *c.fluid->analysis;
  EXPECT_EQ(a.type, FluidAnalysisType::transient);
  EXPECT_EQ(a.cfl, 1.0);
  EXPECT_EQ(a.q_dif, 0.5);
  EXPECT_EQ(a.riemann->normal, Vec3::UnitX());
  EXPECT_EQ(a.riemann->right.velocity, Vec3::UnitX());
  EXPECT_EQ(c.time->step, 0.0);  // not given: the flow takes its step from the CFL number
}

TEST(ReadCaseErrors, FluidAnalysis) {
  EXPECT_EQ(text_error(kFluidCase + "  analysis: { type: transient }\n"),
            at("inline.yaml", 5,
               "fluid.analysis: a transient flow analysis needs a 'time' "
               "section (end; the step follows from cfl)"));
  EXPECT_EQ(text_error(kFluidCase + "  analysis: { type: steady, cfl: 1.5 }\n"),
            at("inline.yaml", 5, "fluid.analysis.cfl: must be in (0, 1], got 1.5"));
  EXPECT_EQ(text_error(kFluidCase + "  analysis: { type: steady, consistent_mass_iterations: 3, cfl: 0.9 }\n"),
            at("inline.yaml", 5, "fluid.analysis.cfl: must be in (0, 0.6], got 0.9"));
  EXPECT_EQ(text_error(kFluidCase + "  analysis: { type: steady, residual_drop: 2 }\n"),
            at("inline.yaml", 5,
               "fluid.analysis.residual_drop: must be in (0, 1), got 2; e.g. 1e-6 "
               "stops once the density rate has dropped by six orders"));
  EXPECT_EQ(text_error(kFluidCase + "  analysis: { type: transient, residual_drop: 1e-3 }\ntime: { end: 1 }\n"),
            at("inline.yaml", 5, "fluid.analysis.residual_drop: applies only to analyses of type 'steady'"));
  const Case steady =
      read_case_string(kFluidCase + "  analysis: { type: steady, residual_drop: 1e-5 }\n", data("inline.yaml"));
  EXPECT_EQ(steady.fluid->analysis->residual_drop, 1e-5);
  EXPECT_FALSE(read_case_string(kFluidCase + "  analysis: { type: steady }\n", data("inline.yaml"))
                   .fluid->analysis->residual_drop);
}

TEST(ReadCase, TimeFunctionsStepAndExpression) {
  const auto load_function = [](const std::string& f) {
    const Case c = read_case_string(
        "name: t\n"
        "meshes: { shell: { geo: panel_strip.geo } }\n"
        "shell:\n"
        "  thickness: 0.1\n"
        "  material: { young_modulus: 1e6, poisson_ratio: 0, density: 1 }\n"
        "  analysis: { type: dynamic, load_function: " +
            f +
            " }\n"
            "time: { end: 1, step: 0.1 }\n",
        data("inline.yaml"));
    return c.shell->analysis->load_function;
  };
  const TimeFunction step = load_function("{ type: step, value: 2, time: 0.5 }");
  EXPECT_EQ(step.value(0.4), 0.0);
  EXPECT_EQ(step.value(0.5), 2.0);
  const TimeFunction smooth = load_function("{ type: smooth_step, value: 2, time: 0, duration: 1 }");
  EXPECT_DOUBLE_EQ(smooth.value(0.5), 1.0);
  EXPECT_DOUBLE_EQ(smooth.derivative(0.5), 3.0);  // 6 V s (1 - s) / T
  const TimeFunction e = load_function("{ type: expression, value: \"0.1*sin(2*pi*20*t)\" }");
  EXPECT_DOUBLE_EQ(e.value(0.0125), 0.1);
  EXPECT_NEAR(e.derivative(0.0), 0.1 * 2 * 3.141592653589793 * 20, 1e-12);
}

TEST(ReadCaseErrors, ExpressionSyntaxNamesLineAndColumn) {
  EXPECT_EQ(text_error("name: t\n"
                       "meshes: { shell: { geo: panel_strip.geo } }\n"
                       "shell:\n"
                       "  thickness: 0.1\n"
                       "  material: { young_modulus: 1e6, poisson_ratio: 0, density: 1 }\n"
                       "  analysis: { type: dynamic, load_function: { type: expression, value: "
                       "\"sin(2*pi*t\" } }\n"
                       "time: { end: 1, step: 0.1 }\n"),
            at("inline.yaml", 6,
               "shell.analysis.load_function.value: expression \"sin(2*pi*t\": "
               "column 11: expected ')'"));
}

TEST(ReadCase, FluidExpressionsMeshMotionAndBoundaryState) {
  const Case c = read_case_string(
      kFluidCase +
          "  boundaries:\n"
          "    - group: inflow\n"
          "      type: supersonic_inflow\n"
          "      state: { density: \"1 + 0.2*sin(2*pi*(x - 2*t))\", velocity: [2, 0, 0], pressure: 1 }\n"
          "  mesh_motion: { displacement: [\"0.05*sin(pi*x)*sin(2*pi*t/0.5)\", 0, \"z*t\"] }\n"
          "  analysis:\n"
          "    type: transient\n"
          "    initial: { density: \"1 + x*y\", velocity: [1, \"y\", 0], pressure: 2 }\n"
          "time: { end: 1 }\n",
      data("inline.yaml"));
  ASSERT_TRUE(c.fluid && c.fluid->mesh_motion && c.fluid->analysis && c.fluid->analysis->initial);
  const auto& state = *c.fluid->boundaries[0].state;
  EXPECT_DOUBLE_EQ(state.density(Vec3(0.25, 0, 0), 0.0), 1.2);
  EXPECT_DOUBLE_EQ(state.velocity[0](Vec3::Zero(), 0.0), 2.0);
  const auto& d = c.fluid->mesh_motion->displacement;
  EXPECT_DOUBLE_EQ(d[0](Vec3(0.5, 0, 0), 0.125), 0.05);
  EXPECT_DOUBLE_EQ(d[2](Vec3(0, 0, 3), 2.0), 6.0);
  EXPECT_DOUBLE_EQ(d[2].time_derivative(Vec3(0, 0, 3), 2.0), 3.0);
  const auto& initial = *c.fluid->analysis->initial;
  EXPECT_DOUBLE_EQ(initial.density(Vec3(2, 3, 0), 0.0), 7.0);
  EXPECT_DOUBLE_EQ(initial.velocity[1](Vec3(2, 3, 0), 0.0), 3.0);
}

TEST(ReadCaseErrors, FluidExpressionsMeshMotionAndBoundaryState) {
  EXPECT_EQ(text_error(kFluidCase + "  mesh_motion: { displacement: [\"sin(q*t)\", 0, 0] }\n"),
            at("inline.yaml", 5,
               "fluid.mesh_motion.displacement[0]: expression \"sin(q*t)\": "
               "column 5: unknown name 'q'; expected x, y, z, t, pi, e or a "
               "function sin cos tan exp log sqrt abs tanh step min max pow "
               "atan2"));
  EXPECT_EQ(text_error(kFluidCase + "  mesh_motion: { displacement: [0, 0] }\n"),
            at("inline.yaml", 5, "fluid.mesh_motion.displacement: expected 3 components, got 2"));
  EXPECT_EQ(text_error(kFluidCase + "  boundaries:\n"
                                    "    - { group: inflow, type: slip_wall, state: { density: 1, "
                                    "pressure: 1 } }\n"),
            at("inline.yaml", 6,
               "fluid.boundaries[0].state: a 'slip_wall' boundary takes no "
               "state; only supersonic_inflow and far_field do"));
  EXPECT_EQ(text_error(kFluidCase + "  mesh_motion: { displacement: [t, 0, 0] }\n"
                                    "  analysis: { type: steady }\n"),
            at("inline.yaml", 5,
               "fluid.mesh_motion: a steady (local time stepping) analysis "
               "needs a fixed mesh; use type: transient or remove 'mesh_motion'"));
  EXPECT_EQ(text_error(kFluidCase + "  analysis:\n"
                                    "    type: transient\n"
                                    "    riemann: { position: 0.5, left: { density: 1, pressure: 1 },\n"
                                    "               right: { density: 1, pressure: 1 } }\n"
                                    "    initial: { density: 1, pressure: 1 }\n"
                                    "time: { end: 1 }\n"),
            at("inline.yaml", 9,
               "fluid.analysis.initial: give either 'riemann' or 'initial', "
               "not both"));
}

TEST(ReadCase, FluidViscosityAndNoSlipWalls) {
  const Case c = read_case_string(
      "name: t\n"
      "meshes: { fluid: { geo: fluid_slab.geo } }\n"
      "fluid:\n"
      "  gas: { viscosity: { law: sutherland, mu_ref: 2e-5, t_ref: 300, sutherland: 100 } }\n"
      "  free_stream: { density: 1, pressure: 1, mach: 0 }\n"
      "  boundaries:\n"
      "    - { group: inflow, type: no_slip_wall, velocity: [1, 0, 0], temperature: 300 }\n"
      "    - { group: outflow, type: no_slip_wall }\n"
      "    - { group: far_field, type: no_slip_wall, velocity: [\"20*y/0.01\", 0, \"t\"] }\n",
      data("inline.yaml"));
  const Viscosity& mu = c.fluid->gas.viscosity;
  EXPECT_EQ(mu.law, ViscosityLaw::sutherland);
  EXPECT_EQ(mu.mu_ref, 2e-5);
  EXPECT_EQ(mu.t_ref, 300.0);
  EXPECT_EQ(mu.sutherland, 100.0);
  EXPECT_EQ(mu.prandtl, 0.72);
  const auto& v = *c.fluid->boundaries[0].wall_velocity;
  const Vec3 x(0.3, 0.005, 0.1);
  EXPECT_EQ(Vec3(v[0](x, 0.0), v[1](x, 0.0), v[2](x, 0.0)), Vec3::UnitX());
  EXPECT_FALSE(c.fluid->boundaries[1].wall_velocity.has_value());
  const auto& profile = *c.fluid->boundaries[2].wall_velocity;  // an inlet profile: expressions of x, y, z, t
  EXPECT_DOUBLE_EQ(profile[0](x, 2.0), 10.0);
  EXPECT_DOUBLE_EQ(profile[2](x, 2.0), 2.0);
  EXPECT_EQ(c.fluid->boundaries[0].wall_temperature, 300.0);
  EXPECT_FALSE(c.fluid->boundaries[1].wall_temperature.has_value());
  const Case power = read_case_string(
      "name: t\n"
      "meshes: { fluid: { geo: fluid_slab.geo } }\n"
      "fluid:\n"
      "  gas: { viscosity: { law: power, exponent: 1, mu_ref: 1.789e-5, t_ref: 288.15 } }\n"
      "  free_stream: { density: 1, pressure: 1, mach: 0 }\n",
      data("inline.yaml"));
  EXPECT_EQ(power.fluid->gas.viscosity.law, ViscosityLaw::power);
  EXPECT_EQ(power.fluid->gas.viscosity.exponent, 1.0);
  EXPECT_EQ(power.fluid->gas.viscosity.t_ref, 288.15);
}

TEST(ReadCaseErrors, FluidViscosityAndNoSlipWalls) {
  const std::string head =
      "name: t\n"
      "meshes: { fluid: { geo: fluid_slab.geo } }\n"
      "fluid:\n";
  EXPECT_EQ(text_error(head + "  gas: { viscosity: { law: sutherlnd } }\n"
                              "  free_stream: { density: 1, pressure: 1, mach: 0 }\n"),
            at("inline.yaml", 4,
               "fluid.gas.viscosity.law: unknown value 'sutherlnd'; did you "
               "mean 'sutherland'? (one of: none, constant, sutherland, power)"));
  EXPECT_EQ(text_error(head + "  free_stream: { density: 1, pressure: 1, mach: 0 }\n"
                              "  boundaries: [ { group: inflow, type: no_slip_wall, temperature: -1 } ]\n"),
            at("inline.yaml", 5, "fluid.boundaries[0].temperature: must be > 0 K, got -1"));
  EXPECT_EQ(text_error(head + "  free_stream: { density: 1, pressure: 1, mach: 0 }\n"
                              "  boundaries: [ { group: inflow, type: slip_wall, temperature: 300 } ]\n"),
            at("inline.yaml", 5,
               "fluid.boundaries[0].temperature: only no_slip_wall boundaries take "
               "a wall temperature"));
}

TEST(ReadCase, ShellPathControlAndTimeScheme) {
  const std::string head =
      "name: t\n"
      "meshes: { shell: { geo: panel_strip.geo } }\n"
      "shell:\n"
      "  thickness: 0.1\n"
      "  material: { young_modulus: 1e6, poisson_ratio: 0, density: 1 }\n";
  const Case d = read_case_string(head +
                                      "  analysis: { type: static, steps: 5, control: displacement,\n"
                                      "              controlled: { group: panel, component: y }, final_value: -0.2 }\n",
                                  data("inline.yaml"));
  EXPECT_EQ(d.shell->analysis->control, PathControl::displacement);
  EXPECT_EQ(d.shell->analysis->controlled_group, "panel");
  EXPECT_EQ(d.shell->analysis->controlled_component, 1);
  EXPECT_EQ(d.shell->analysis->final_displacement, -0.2);
  const Case a = read_case_string(head +
                                      "  analysis: { type: static, control: arc_length, initial_load_increment: 0.05,\n"
                                      "              final_load_factor: 3 }\n",
                                  data("inline.yaml"));
  EXPECT_EQ(a.shell->analysis->control, PathControl::arc_length);
  EXPECT_EQ(a.shell->analysis->initial_load_increment, 0.05);
  EXPECT_EQ(a.shell->analysis->final_load_factor, 3.0);
  const Case m = read_case_string(
      head + "  analysis: { type: dynamic, scheme: midpoint, newton: modified }\ntime: { end: 1, step: 0.1 }\n",
      data("inline.yaml"));
  EXPECT_EQ(m.shell->analysis->scheme, TimeScheme::midpoint);
  EXPECT_TRUE(m.shell->analysis->modified_newton);
  EXPECT_EQ(text_error(head + "  analysis: { type: static, control: arc_length, newton: modified }\n"),
            at("inline.yaml", 6,
               "shell.analysis.newton: 'modified' applies to load control and dynamics; "
               "displacement control and arc length use full Newton"));
  EXPECT_EQ(text_error(head + "  analysis: { type: static, control: displacement,\n"
                              "              controlled: { group: panel, node: 3, component: y },\n"
                              "              final_value: 1 }\n"),
            at("inline.yaml", 7,
               "shell.analysis.controlled: expected exactly one of 'group' "
               "(its mean displacement) and 'node'"));
  EXPECT_EQ(text_error(head + "  analysis: { type: dynamic, scheme: midpiont }\n"
                              "time: { end: 1, step: 0.1 }\n"),
            at("inline.yaml", 6,
               "shell.analysis.scheme: unknown value 'midpiont'; did you mean "
               "'midpoint'? (one of: newmark, midpoint)"));
}

}  // namespace
}  // namespace shellflow::io

namespace shellflow::io {
namespace {

TEST(ReadCase, ShellModalAnalysis) {
  const std::string head =
      "name: t\n"
      "meshes: { shell: { geo: panel_strip.geo } }\n"
      "shell:\n"
      "  thickness: 0.1\n"
      "  material: { young_modulus: 1e6, poisson_ratio: 0, density: 1 }\n";
  // No time section needed; defaults of ModalOptions.
  const Case d = read_case_string(head + "  analysis: { type: modal }\n", data("inline.yaml"));
  ASSERT_TRUE(d.shell && d.shell->analysis);
  EXPECT_EQ(d.shell->analysis->type, ShellAnalysisType::modal);
  EXPECT_EQ(d.shell->analysis->modes, 10);
  EXPECT_EQ(d.shell->analysis->modal_tolerance, 1e-8);
  EXPECT_EQ(d.shell->analysis->modal_max_iterations, 300);
  EXPECT_FALSE(d.time);
  const Case m = read_case_string(
      head + "  analysis: { type: modal, modes: 200, tolerance: 1e-6, max_iterations: 50 }\n", data("inline.yaml"));
  EXPECT_EQ(m.shell->analysis->modes, 200);
  EXPECT_EQ(m.shell->analysis->modal_tolerance, 1e-6);
  EXPECT_EQ(m.shell->analysis->modal_max_iterations, 50);

  EXPECT_EQ(text_error(head + "  analysis: { type: modal, modes: 0 }\n"),
            at("inline.yaml", 6, "shell.analysis.modes: must be in [1, 200], got 0"));
  EXPECT_EQ(text_error(head + "  analysis: { type: modal, modes: 201 }\n"),
            at("inline.yaml", 6, "shell.analysis.modes: must be in [1, 200], got 201"));
  EXPECT_EQ(text_error(head + "  analysis: { type: modal, tolerance: 0 }\n"),
            at("inline.yaml", 6, "shell.analysis.tolerance: must be in (0, 1), got 0"));
  EXPECT_EQ(text_error(head + "  analysis:\n    type: modal\n    scheme: midpoint\n"),
            at("inline.yaml", 8,
               "shell.analysis.scheme: applies only to analyses of type 'dynamic'; "
               "a modal analysis takes 'modes', 'tolerance' and 'max_iterations'"));
  EXPECT_EQ(text_error(head + "  analysis: { type: modal, steps: 3 }\n"),
            at("inline.yaml", 6,
               "shell.analysis.steps: applies only to analyses of type 'static'; "
               "a modal analysis takes 'modes', 'tolerance' and 'max_iterations'"));
  EXPECT_EQ(text_error(head + "  analysis: { type: modal, newton: full }\n"),
            at("inline.yaml", 6,
               "shell.analysis.newton: applies only to analyses of type 'static' or "
               "'dynamic'; a modal analysis takes 'modes', 'tolerance' and 'max_iterations'"));
  EXPECT_EQ(text_error(head + "  analysis: { type: modal, mods: 3 }\n"),
            at("inline.yaml", 6, "shell.analysis.mods: unknown key; did you mean 'modes'?"));
  EXPECT_EQ(text_error(head + "  analysis: { type: static, modes: 3 }\n"),
            at("inline.yaml", 6, "shell.analysis.modes: applies only to analyses of type 'modal'"));
  EXPECT_EQ(text_error("name: t\n"
                       "meshes: { shell: { geo: panel_strip.geo } }\n"
                       "shell:\n"
                       "  thickness: 0.1\n"
                       "  material: { young_modulus: 1e6, poisson_ratio: 0, density: 0 }\n"
                       "  analysis: { type: modal }\n"),
            at("inline.yaml", 6,
               "shell.analysis.type: a modal analysis needs the shell's mass; set "
               "shell.material.density > 0"));
}

}  // namespace
}  // namespace shellflow::io

namespace shellflow::io {
namespace {

// A piston-theory coupled case with `extra` appended to its coupling section.
std::string coupled_text(const std::string& extra) {
  return "name: t\n"
         "meshes: { shell: { geo: panel_strip.geo, order: 3 } }\n"
         "shell:\n"
         "  thickness: 1.35e-3\n"
         "  material: { young_modulus: 77.28e9, poisson_ratio: 0.33, density: 2710 }\n"
         "  analysis: { type: dynamic }\n"
         "fluid:\n"
         "  model: piston_theory\n"
         "  free_stream: { density: 0.339, pressure: 28000, mach: 2.3, direction: [1, 0, 0] }\n"
         "time: { end: 0.01, step: 1.0e-4 }\n"
         "coupling:\n"
         "  wet_normal: [0, 1, 0]\n" +
         extra;
}

TEST(ReadCaseCoupling, IterationsAndAccelerationKeys) {
  const Case loose = read_case_string(coupled_text(""), data("inline.yaml"));
  EXPECT_EQ(loose.coupling->iterations, 1);
  EXPECT_EQ(loose.coupling->tolerance, 1e-6);
  EXPECT_EQ(loose.coupling->acceleration.type, CouplingSection::Acceleration::Type::none);
  const Case aitken = read_case_string(coupled_text("  iterations: 20\n  tolerance: 1e-8\n  acceleration: aitken\n"),
                                       data("inline.yaml"));
  EXPECT_EQ(aitken.coupling->iterations, 20);
  EXPECT_EQ(aitken.coupling->tolerance, 1e-8);
  EXPECT_EQ(aitken.coupling->acceleration.type, CouplingSection::Acceleration::Type::aitken);
  EXPECT_EQ(aitken.coupling->acceleration.relaxation, 0.5);
  const Case iqn = read_case_string(
      coupled_text("  iterations: 30\n  acceleration: { type: iqn_ils, relaxation: 0.1, columns: 40, reuse: 3, "
                   "filter: 1e-3 }\n"),
      data("inline.yaml"));
  const auto& a = iqn.coupling->acceleration;
  EXPECT_EQ(a.type, CouplingSection::Acceleration::Type::iqn_ils);
  EXPECT_EQ(a.relaxation, 0.1);
  EXPECT_EQ(a.columns, 40);
  EXPECT_EQ(a.reuse, 3);
  EXPECT_EQ(a.filter, 1e-3);
}

TEST(ReadCaseCoupling, IterationsAndAccelerationErrors) {
  EXPECT_EQ(text_error(coupled_text("  acceleration: iqn_ils\n")),
            at("inline.yaml", 13,
               "coupling.acceleration: an acceleration acts between coupling iterations: set 'iterations' above 1 "
               "(e.g. 20)"));
  EXPECT_EQ(text_error(coupled_text("  iterations: 0\n")),
            at("inline.yaml", 13, "coupling.iterations: must be in [1, 1000], got 0"));
  EXPECT_EQ(text_error(coupled_text("  iterations: 5\n  acceleration: iqn\n")),
            at("inline.yaml", 14,
               "coupling.acceleration: unknown value 'iqn'; expected one of: none, constant, aitken, iqn_ils"));
  // Only the keys of the acceleration's type.
  EXPECT_EQ(text_error(coupled_text("  iterations: 5\n  acceleration: { type: aitken, columns: 5 }\n")),
            at("inline.yaml", 14, "coupling.acceleration.columns: unknown key; expected one of: type, relaxation"));
  EXPECT_EQ(text_error(coupled_text("  iterations: 5\n  acceleration: { type: iqn_ils, filter: 1 }\n")),
            at("inline.yaml", 14, "coupling.acceleration.filter: must be in [0, 1), got 1"));
  EXPECT_EQ(text_error(coupled_text("  scheme: monolithic\n  iterations: 5\n")),
            at("inline.yaml", 14,
               "coupling.iterations: the monolithic scheme solves the coupling inside the shell's Newton "
               "iteration: remove 'iterations' (or use scheme: staggered)"));
}

TEST(ReadCaseCoupling, Identification) {
  const Case c =
      read_case_string(coupled_text("  identification: { modes: 4, pulse_width: 1e-3, gap: 4e-3, amplitude: 2e-6 }\n"),
                       data("inline.yaml"));
  ASSERT_TRUE(c.coupling->identification);
  EXPECT_EQ(c.coupling->identification->modes, 4);
  EXPECT_EQ(c.coupling->identification->pulse_width, 1e-3);
  EXPECT_EQ(c.coupling->identification->gap, 4e-3);
  EXPECT_EQ(c.coupling->identification->amplitude, 2e-6);
  const Case defaults = read_case_string(coupled_text("  identification: {}\n"), data("inline.yaml"));
  EXPECT_EQ(defaults.coupling->identification->modes, 6);
  EXPECT_EQ(defaults.coupling->identification->pulse_width, 0.0);  // auto
  EXPECT_FALSE(read_case_string(coupled_text(""), data("inline.yaml")).coupling->identification);
  EXPECT_EQ(text_error(coupled_text("  identification: { modes: 0 }\n")),
            at("inline.yaml", 13, "coupling.identification.modes: must be in [1, 40], got 0"));
  EXPECT_EQ(text_error(coupled_text("  identification: { amplitude: 0.01 }\n")),
            at("inline.yaml", 13, "coupling.identification.amplitude: must be in (0, 0.001) m, got 0.01"));
  EXPECT_EQ(text_error(coupled_text("  identification: { width: 1e-3 }\n")),
            at("inline.yaml", 13,
               "coupling.identification.width: unknown key; expected one of: modes, pulse_width, gap, amplitude"));
  EXPECT_EQ(text_error(coupled_text("  iterations: 5\n  identification: {}\n")),
            at("inline.yaml", 14,
               "coupling.identification: an identification run prescribes the wall's motion: it has no coupling "
               "iterations; remove coupling.iterations"));
}

}  // namespace
}  // namespace shellflow::io

namespace shellflow::io {
namespace {

TEST(ReadCaseErrors, AbsurdStepCountsAreRefused) {
  // 1e300 / 1e-4 steps would overflow the step counter: refused with the keys.
  EXPECT_EQ(text_error(coupled_text("").replace(coupled_text("").find("end: 0.01"), 9, "end: 1e300")),
            at("inline.yaml", 10,
               "time.end: time.end / time.step = 1e+304 steps; a run takes at most 1e+09 steps: shorten time.end "
               "or lengthen time.step"));
  EXPECT_NO_THROW(read_case_string(coupled_text(""), data("inline.yaml")));
}

}  // namespace
}  // namespace shellflow::io
