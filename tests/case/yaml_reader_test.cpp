// The YAML reader every case-file section goes through: values, defaults, ranges, key paths,
// line numbers and the one-line error messages.
#include "shellflow/io/yaml_reader.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <future>
#include <memory>
#include <string>
#include <thread>

#include "shellflow/core/error.h"

namespace shellflow::io {
namespace {

// The message of the InputError `f` throws ("" and a test failure if it throws none).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError thrown";
  return {};
}

YamlNode load(std::string_view text) { return YamlNode::load_string(text, "cases/t.yaml"); }

TEST(EditDistance, CountsInsertionsDeletionsSubstitutionsAndSwaps) {
  EXPECT_EQ(edit_distance("order", "order"), 0u);
  EXPECT_EQ(edit_distance("ordr", "order"), 1u);
  EXPECT_EQ(edit_distance("oredr", "order"), 1u);  // neighbour swap counts once
  EXPECT_EQ(edit_distance("orders", "order"), 1u);
  EXPECT_EQ(edit_distance("odrer", "order"), 1u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
}

TEST(ClosestMatch, SuggestsLikelyMisspellingsOnly) {
  const std::vector<std::string> keys = {"thickness", "material", "supports"};
  EXPECT_EQ(closest_match("thicknes", keys), "thickness");
  EXPECT_EQ(closest_match("Thickness", keys), "thickness");
  EXPECT_EQ(closest_match("suports", keys), "supports");
  EXPECT_EQ(closest_match("materials", keys), "material");
  EXPECT_EQ(closest_match("poisson", {"poisson_ratio", "density"}), "poisson_ratio");
  EXPECT_FALSE(closest_match("density", keys).has_value());
  EXPECT_FALSE(closest_match("x", keys).has_value());
}

TEST(Range, DescribesItselfWithUnit) {
  EXPECT_EQ(Range::positive().describe("m"), "> 0 m");
  EXPECT_EQ(Range::non_negative().describe(), ">= 0");
  EXPECT_EQ(Range::at_least(1).describe(), ">= 1");
  EXPECT_EQ(Range::open(-1, 0.5).describe(), "in (-1, 0.5)");
  EXPECT_EQ(Range::in_range(1, 3).describe(), "in [1, 3]");
  EXPECT_EQ(Range::any().describe("m"), "");
  EXPECT_TRUE(Range::positive().contains(1e-300));
  EXPECT_FALSE(Range::positive().contains(0.0));
  EXPECT_TRUE(Range::non_negative().contains(0.0));
  EXPECT_FALSE(Range::open(-1, 0.5).contains(0.5));
  EXPECT_TRUE(Range::in_range(1, 3).contains(3.0));
}

TEST(YamlNode, ReadsScalarsOfEachType) {
  const YamlNode root = load("a: 1.5e-3\nb: 42\nc: yes\nd: hello world\ne: +7\n");
  EXPECT_DOUBLE_EQ(root.required<double>("a"), 1.5e-3);
  EXPECT_EQ(root.required<int>("b"), 42);
  EXPECT_DOUBLE_EQ(root.required<double>("b"), 42.0);
  EXPECT_TRUE(root.required<bool>("c"));
  EXPECT_EQ(root.required<std::string>("d"), "hello world");
  EXPECT_EQ(root.required<long>("e"), 7);
  EXPECT_NO_THROW(root.finish());
}

TEST(YamlNode, OptionalKeysTakeTheirDefault) {
  const YamlNode root = load("a: 2\n");
  EXPECT_EQ(root.optional<int>("a", 1), 2);
  EXPECT_EQ(root.optional<int>("missing", 1), 1);
  EXPECT_EQ(root.optional<std::string>("s", "dflt"), "dflt");
  EXPECT_FALSE(root.maybe<double>("x").has_value());
  EXPECT_EQ(root.choice("kind", {"a", "b"}, "b"), "b");
  EXPECT_EQ(root.vec3("v", Vec3(1, 2, 3)), Vec3(1, 2, 3));
  EXPECT_NO_THROW(root.finish());
}

TEST(YamlNode, WrongTypesNameTheKeyAndWhatWasExpected) {
  const YamlNode root = load("a: abc\nb: 1.5\nc: [1, 2]\nd: {x: 1}\ne: maybe\nf:\ng: 300\n");
  EXPECT_EQ(error_of([&] { root.required<double>("a"); }), "cases/t.yaml:1: a: expected a number, got 'abc'");
  EXPECT_EQ(error_of([&] { root.required<int>("b"); }), "cases/t.yaml:2: b: expected an integer, got '1.5'");
  EXPECT_EQ(error_of([&] { root.required<double>("c"); }), "cases/t.yaml:3: c: expected a number, got a list");
  EXPECT_EQ(error_of([&] { root.required<std::string>("d"); }), "cases/t.yaml:4: d: expected a string, got a map");
  EXPECT_EQ(error_of([&] { root.required<bool>("e"); }), "cases/t.yaml:5: e: expected true or false, got 'maybe'");
  EXPECT_EQ(error_of([&] { root.required<double>("f"); }), "cases/t.yaml:6: f: expected a number, got an empty value");
  EXPECT_EQ(error_of([&] { root.required<std::int8_t>("g"); }), "cases/t.yaml:7: g: must be in [-128, 127], got '300'");
  EXPECT_EQ(error_of([&] { root.list("d"); }), "cases/t.yaml:4: d: expected a list, got a map");
  EXPECT_EQ(error_of([&] { root.child("c"); }), "cases/t.yaml:3: c: expected a map of keys, got a list");
}

TEST(YamlNode, RangeErrorsQuoteTheValueAsWritten) {
  const YamlNode root = load("shell:\n  thickness: -0.001\n  nu: 0.50\n  n: 0\n");
  const YamlNode shell = root.child("shell");
  EXPECT_EQ(error_of([&] { shell.required<double>("thickness", Range::positive(), "m"); }),
            "cases/t.yaml:2: shell.thickness: must be > 0 m, got -0.001");
  EXPECT_EQ(error_of([&] { shell.required<double>("nu", Range::open(-1, 0.5)); }),
            "cases/t.yaml:3: shell.nu: must be in (-1, 0.5), got 0.50");
  EXPECT_EQ(error_of([&] { shell.optional<int>("n", 1, Range::at_least(1)); }),
            "cases/t.yaml:4: shell.n: must be >= 1, got 0");
}

TEST(YamlNode, MissingRequiredKeyIsReportedAtTheMap) {
  const YamlNode root = load("name: x\nmeshes:\n  space:\n    order: 3\n");
  const YamlNode space = root.child("meshes").child("space");
  EXPECT_EQ(space.line(), 3);
  EXPECT_EQ(space.key_path(), "meshes.space");
  EXPECT_EQ(error_of([&] {
              space.fail_missing({"geo", "msh"});
            }),
            "cases/t.yaml:3: meshes.space: missing required key 'geo' or 'msh'");
  EXPECT_EQ(error_of([&] { root.required<std::string>("title"); }), "cases/t.yaml:1: missing required key 'title'");
}

TEST(YamlNode, MissingRequiredKeyNextToAMisspellingReportsTheMisspelling) {
  const YamlNode root = load("shell:\n  material: {}\n  thicknes: 1e-3\n");
  const YamlNode shell = root.child("shell");
  EXPECT_EQ(error_of([&] { shell.required<double>("thickness"); }),
            "cases/t.yaml:3: shell.thicknes: unknown key; did you mean 'thickness'?");
}

TEST(YamlNode, FinishReportsTheFirstUnreadKeyWithASuggestion) {
  const YamlNode root = load(
      "meshes:\n"
      "  fluid:\n"
      "    geo: a.geo\n"
      "    ordr: 1\n"
      "  extra: 1\n");
  const YamlNode fluid = root.child("meshes").child("fluid");
  fluid.required<std::string>("geo");
  fluid.optional<int>("order", 1);
  fluid.optional<double>("size_factor", 1.0);
  EXPECT_EQ(error_of([&] { fluid.finish(); }), "cases/t.yaml:4: meshes.fluid.ordr: unknown key; did you mean 'order'?");
  // From the root, every unread key below is found, in document order.
  root.child("meshes").has("space");
  const auto unread = root.unread_keys();
  ASSERT_EQ(unread.size(), 2u);
  EXPECT_EQ(unread[1], "cases/t.yaml:5: meshes.extra: unknown key; expected one of: fluid, space");
  EXPECT_EQ(error_of([&] { root.finish(); }),
            "cases/t.yaml:4: meshes.fluid.ordr: unknown key; did you mean 'order'? "
            "(and 1 more unknown key)");
}

TEST(YamlNode, ListItemsCarryIndexedPathsAndTheirOwnLines) {
  const YamlNode root = load(
      "supports:\n"
      "  - { group: a, type: clamped }\n"
      "  - group: b\n"
      "    type: clampd\n");
  const auto items = root.list("supports");
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[0].key_path(), "supports[0]");
  EXPECT_EQ(items[1].line(), 3);
  EXPECT_EQ(items[0].choice("type", {"clamped", "sliding"}), "clamped");
  EXPECT_EQ(error_of([&] {
              items[1].choice("type", {"clamped", "sliding"});
            }),
            "cases/t.yaml:4: supports[1].type: unknown value 'clampd'; did you mean 'clamped'? "
            "(one of: clamped, sliding)");
  EXPECT_EQ(items[1].location("group").message("x"), "cases/t.yaml:3: supports[1].group: x");
  // Groups were never read: finish() on the root sees into the items.
  EXPECT_EQ(error_of([&] { root.finish(); }),
            "cases/t.yaml:2: supports[0].group: unknown key; expected one of: type "
            "(and 1 more unknown key)");
}

TEST(YamlNode, Vec3NeedsExactlyThreeNumbers) {
  const YamlNode root = load("a: [1, 2.5, -3]\nb: [1, 2]\nc: [1, x, 3]\nd: 4\n");
  EXPECT_EQ(root.vec3("a"), Vec3(1, 2.5, -3));
  EXPECT_EQ(error_of([&] { root.vec3("b"); }),
            "cases/t.yaml:2: b: expected a list of 3 numbers [x, y, z], got a list of 2 items");
  EXPECT_EQ(error_of([&] { root.vec3("c"); }), "cases/t.yaml:3: c[1]: expected a number, got 'x'");
  EXPECT_EQ(error_of([&] { root.vec3("d"); }), "cases/t.yaml:4: d: expected a list of 3 numbers [x, y, z], got '4'");
}

TEST(YamlNode, DuplicateKeysAreErrors) {
  EXPECT_EQ(error_of([] { load("a: 1\nb: 2\na: 3\n"); }),
            "cases/t.yaml:3: a: duplicate key; it was first given at line 1");
}

TEST(YamlNode, SyntaxErrorsAndNonMapDocumentsAreReportedWithTheirLine) {
  const std::string syntax = error_of([] { load("a: 1\nb: [1, 2\nc: 3\n"); });
  EXPECT_EQ(syntax.rfind("cases/t.yaml:", 0), 0u) << syntax;
  EXPECT_NE(syntax.find(": YAML syntax error: "), std::string::npos) << syntax;
  EXPECT_EQ(error_of([] { load(""); }),
            "cases/t.yaml:1: expected a map of keys at the top level, got an empty document");
  EXPECT_EQ(error_of([] { load("- 1\n- 2\n"); }),
            "cases/t.yaml:1: expected a map of keys at the top level, got a list");
  EXPECT_EQ(error_of([] { load("a: 1\n---\nb: 2\n"); }),
            "cases/t.yaml:3: expected one YAML document, found 2; remove the '---' separators");
}

TEST(YamlNode, MalformedStreamsFailFastWithOneLine) {
  // yaml-cpp 0.7's LoadAll loops forever (memory growing) on some of these, e.g. a lone ','.
  const std::vector<std::string> inputs = {",", "]",    "{",       "- [", ": :", "---", "}",
                                           "[", ",\n,", "a: 1\n,", "- ]", "&a",  "*a",  "? "};
  for (const std::string& text : inputs) {
    auto done = std::make_shared<std::promise<std::string>>();
    auto result = done->get_future();
    std::thread([text, done] {
      try {
        load(text);
        done->set_value("");
      } catch (const InputError& e) {
        done->set_value(e.what());
      } catch (const std::exception& e) {
        done->set_value(std::string("not an InputError: ") + e.what());
      }
    }).detach();
    if (result.wait_for(std::chrono::seconds(1)) != std::future_status::ready) {
      ADD_FAILURE() << "reading '" << text << "' did not finish within 1 s";
      std::fflush(nullptr);
      std::_Exit(1);  // the parser thread cannot be stopped; stop before memory runs out
    }
    const std::string msg = result.get();
    EXPECT_EQ(msg.rfind("cases/t.yaml:", 0), 0u) << "'" << text << "': " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  EXPECT_EQ(error_of([] { load(","); }),
            "cases/t.yaml:1: YAML syntax error: unexpected ','; check the brackets, "
            "quotes, ':' and indentation of this line and the one before it");
  // A control byte is shown as \xNN (not sent to the terminal); a tab in the indentation is named.
  EXPECT_EQ(error_of([] { load("\x1b"); }).find('\x1b'), std::string::npos);
  EXPECT_EQ(error_of([] { load("a:\n\tb: 1\n"); }),
            "cases/t.yaml:2: YAML syntax error: illegal map value; indent with spaces: YAML does not allow "
            "tabs there");
  EXPECT_EQ(error_of([] { load("a: 1\n---\nb: 2\n---\nc: 3\n"); }),
            "cases/t.yaml:3: expected one YAML document, found 3; remove the '---' separators");
  // '---' inside a block scalar is text, not a separator.
  EXPECT_EQ(load("a: |\n  ---\n  x\nb: 2\n").required<std::string>("a"), "---\nx\n");
}

TEST(YamlNode, FilesAreResolvedRelativeToTheCaseFile) {
  const std::string dir = SHELLFLOW_TEST_DATA_DIR;
  const YamlNode root = YamlNode::load_string("a: fluid_slab.geo\nb: nothere.geo\nc: .\n", dir + "/x.yaml");
  EXPECT_EQ(root.input_file("a"), std::filesystem::path(dir + "/fluid_slab.geo").lexically_normal());
  EXPECT_EQ(error_of([&] { root.input_file("b"); }),
            dir + "/x.yaml:2: b: file not found: 'nothere.geo' (looked for '" + dir +
                "/nothere.geo'); paths are relative to the case file's directory");
  EXPECT_NE(error_of([&] { root.input_file("c"); }).find("is a directory"), std::string::npos);
  EXPECT_EQ(root.input_file("b", false).filename(), "nothere.geo");
}

TEST(YamlNode, MissingFileIsReportedWithoutLine) {
  EXPECT_EQ(error_of([] { YamlNode::load_file("no/such/case.yaml"); }),
            "no/such/case.yaml: cannot open case file (no such file)");
}

TEST(YamlNode, CopiesShareWhatWasRead) {
  const YamlNode root = load("a: 1\nb: 2\n");
  const YamlNode copy = root;  // NOLINT(performance-unnecessary-copy-initialization)
  copy.required<int>("a");
  root.required<int>("b");
  EXPECT_NO_THROW(root.finish());
  EXPECT_NO_THROW(copy.finish());
}

}  // namespace
}  // namespace shellflow::io
