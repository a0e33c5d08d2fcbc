// PVD collection writer: the file is valid XML after construction and after every add,
// and Python's xml.etree reads back every dataset with its exact time, part and path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "io_test_util.h"
#include "shellflow/core/error.h"
#include "shellflow/io/pvd_writer.h"

namespace shellflow::io {
namespace {

using test::TempDir;

struct DataSet {
  double time;
  int part;
  std::string group, file;
  bool operator==(const DataSet&) const = default;
};

/// Reads `pvd` with data/check_pvd.py (xml.etree); fails the test if it cannot.
std::vector<DataSet> read_pvd(const std::filesystem::path& pvd) {
  const auto r = test::run_python("check_pvd.py", {pvd.string()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::vector<DataSet> out;
  std::size_t count = 0;
  for (const auto& line : test::split_lines(r.output)) {
    std::istringstream in(line);
    std::string tag;
    in >> tag;
    if (tag == "COUNT") {
      in >> count;
    } else if (tag == "DATASET") {
      std::string time_text, group;
      DataSet d{};
      in >> time_text >> d.part >> group;
      std::getline(in >> std::ws, d.file);               // the rest of the line: paths may hold spaces
      d.time = std::strtod(time_text.c_str(), nullptr);  // Python's repr round-trips
      d.group = group.substr(1, group.size() - 2);
      out.push_back(d);
    }
  }
  EXPECT_EQ(out.size(), count) << r.output;
  return out;
}

TEST(PvdWriter, FileIsAValidCollectionAfterEveryAdd) {
  TempDir dir("pvd");
  PvdWriter pvd(dir / "out", "fluid");
  EXPECT_EQ(pvd.path(), dir / "out" / "fluid.pvd");
  EXPECT_TRUE(read_pvd(pvd.path()).empty());  // written, empty, at construction

  const double t1 = 0.1 + 0.2;  // not a short decimal: needs all 17 digits
  std::vector<DataSet> expected;
  pvd.add(0.0, "fluid/fluid_000000.vtu");
  expected.push_back({0.0, 0, "", "fluid/fluid_000000.vtu"});
  EXPECT_EQ(read_pvd(pvd.path()), expected);

  pvd.add(t1, "fluid/fluid_000001.vtu");
  expected.push_back({t1, 0, "", "fluid/fluid_000001.vtu"});
  EXPECT_EQ(read_pvd(pvd.path()), expected);

  pvd.add(t1, "fluid/wall_000001.vtu", 1);  // second part of the same step
  expected.push_back({t1, 1, "", "fluid/wall_000001.vtu"});
  pvd.add(2.5e-7, "fluid/odd name & <x>.vtu");
  expected.push_back({2.5e-7, 0, "", "fluid/odd name & <x>.vtu"});
  EXPECT_EQ(read_pvd(pvd.path()), expected);  // times compare exactly
  EXPECT_NE(test::read_text(pvd.path()).find("odd name &amp; &lt;x&gt;.vtu"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(pvd.path().string() + ".tmp"));
}

TEST(PvdWriter, SameTimeAndPartReplacesTheEntry) {
  TempDir dir("pvd-replace");
  PvdWriter pvd(dir.path(), "shell");
  pvd.add(1.0, "a.vtu");
  pvd.add(1.0, "b.vtu");
  pvd.add(1.0, "c.vtu", 2);
  const auto got = read_pvd(pvd.path());
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0], (DataSet{1.0, 0, "", "b.vtu"}));
  EXPECT_EQ(got[1], (DataSet{1.0, 2, "", "c.vtu"}));
  EXPECT_EQ(pvd.entries().size(), 2u);
}

TEST(PvdWriter, BadInputThrowsAndKeepsTheFile) {
  TempDir dir("pvd-bad");
  EXPECT_THROW(PvdWriter(dir.path(), ""), InputError);
  EXPECT_THROW(PvdWriter(dir.path(), "a/b"), InputError);
  PvdWriter pvd(dir.path(), "space");
  pvd.add(0.5, "space_000000.vtu");
  const auto before = test::read_text(pvd.path());
  EXPECT_THROW(pvd.add(std::nan(""), "x.vtu"), Error);
  EXPECT_THROW(pvd.add(INFINITY, "x.vtu"), Error);
  EXPECT_THROW(pvd.add(1.0, "x.vtu", -1), Error);
  EXPECT_THROW(pvd.add(1.0, ""), Error);
  EXPECT_THROW(pvd.add(1.0, "/abs/x.vtu"), Error);
  EXPECT_EQ(test::read_text(pvd.path()), before);
  EXPECT_EQ(pvd.entries().size(), 1u);
}

}  // namespace
}  // namespace shellflow::io
