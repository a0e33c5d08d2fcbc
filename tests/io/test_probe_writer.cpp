// Probe CSV writer: header, one flushed row per append, values round-trip exactly (read
// back both here with strtod and by Python's csv module), bad names are InputErrors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "io_test_util.h"
#include "shellflow/core/error.h"
#include "shellflow/io/probe_writer.h"

namespace shellflow::io {
namespace {

using test::TempDir;

std::vector<double> parse_row(const std::string& line) {
  std::vector<double> v;
  std::istringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) {
    char* end = nullptr;
    v.push_back(std::strtod(cell.c_str(), &end));
    EXPECT_EQ(*end, '\0') << "unparsed text in '" << cell << "'";
  }
  return v;
}

TEST(ProbeWriter, HeaderAndRowsRoundTripToFullPrecision) {
  TempDir dir("csv");
  const auto file = dir / "probes" / "probes.csv";  // directory is created
  const std::vector<std::vector<double>> rows = {
      {0.0, 1.0 / 3.0, -2.5e17, std::numbers::pi},
      {1e-300, 0.1 + 0.2, 5e-324, -0.0},
      {1.0 / 7.0, std::numeric_limits<double>::max(), -1.0, 123456789.123456789},
  };
  {
    ProbeWriter w(file, {"p_tip", "w_mid", "u.x-1"});
    for (const auto& r : rows) w.append(r[0], std::span<const double>(r).subspan(1));
    EXPECT_EQ(w.rows(), 3u);
  }
  const auto lines = test::split_lines(test::read_text(file));
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], "time,p_tip,w_mid,u.x-1");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(parse_row(lines[i + 1]), rows[i]) << lines[i + 1];
  }

  // An independent reader: Python's csv module, values printed with repr().
  const auto r = test::run_python("check_csv.py", {file.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto out = test::split_lines(r.output);
  ASSERT_EQ(out.size(), 4u) << r.output;
  EXPECT_EQ(out[0], "HEADER time|p_tip|w_mid|u.x-1");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    std::istringstream in(out[i + 1].substr(4));
    std::vector<double> got;
    for (std::string s; in >> s;) got.push_back(std::strtod(s.c_str(), nullptr));
    EXPECT_EQ(got, rows[i]) << out[i + 1];
  }
}

TEST(ProbeWriter, EachRowIsOnDiskAsSoonAsItIsAppended) {
  TempDir dir("csv-flush");
  const auto file = dir / "p.csv";
  ProbeWriter w(file, {"a"});
  EXPECT_EQ(test::read_text(file), "time,a\n");  // header flushed at construction
  for (int i = 1; i <= 3; ++i) {
    const double v = 0.5 * i;
    w.append(0.25 * i, std::span<const double>(&v, 1));
    EXPECT_EQ(test::split_lines(test::read_text(file)).size(), static_cast<std::size_t>(i + 1));
  }
  EXPECT_EQ(test::split_lines(test::read_text(file)).back(), "0.75,1.5");
}

TEST(ProbeWriter, NonFiniteValuesAreWrittenAsNanAndInf) {
  TempDir dir("csv-nan");
  const auto file = dir / "p.csv";
  ProbeWriter w(file, {"a", "b", "c"});
  const std::vector<double> v = {std::nan(""), INFINITY, -INFINITY};
  w.append(1.0, v);
  EXPECT_EQ(test::split_lines(test::read_text(file)).back(), "1,nan,inf,-inf");
  const auto r = test::run_python("check_csv.py", {file.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(test::split_lines(r.output).back(), "ROW 1.0 nan inf -inf");
}

TEST(ProbeWriter, BadNamesAreInputErrorsNamingTheProbe) {
  TempDir dir("csv-names");
  const auto file = dir / "p.csv";
  auto expect_bad = [&](std::vector<std::string> names, const std::string& words) {
    try {
      ProbeWriter w(file, std::move(names));
      ADD_FAILURE() << "accepted names, expected: " << words;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(words), std::string::npos) << msg;
      EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
    }
  };
  expect_bad({"a", "b,c"}, "'b,c' contains a comma");
  expect_bad({"line\nbreak"}, "line break");
  expect_bad({"cr\r"}, "line break");
  expect_bad({"q\"uote"}, "double quote");
  expect_bad({""}, "is empty");
  expect_bad({"time"}, "'time'");
  expect_bad({" padded"}, "space");
  expect_bad({"a", "b", "a"}, "'a' is given twice");
  EXPECT_FALSE(std::filesystem::exists(file)) << "nothing is written for bad names";
  EXPECT_NO_THROW(ProbeWriter(file, {}));  // no probes: a time column only
}

TEST(ProbeWriter, WrongValueCountOrTimeThrows) {
  TempDir dir("csv-count");
  ProbeWriter w(dir / "p.csv", {"a", "b"});
  const std::vector<double> one = {1.0};
  const std::vector<double> two = {1.0, 2.0};
  EXPECT_THROW(w.append(0.0, one), Error);
  EXPECT_THROW(w.append(std::nan(""), two), Error);
  EXPECT_EQ(w.rows(), 0u);
  w.append(0.0, two);
  EXPECT_EQ(w.rows(), 1u);
}

}  // namespace
}  // namespace shellflow::io
