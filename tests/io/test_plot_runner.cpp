// io::PlotRunner: several plots drawn by one tools/plot_run.py process; a failing plot is a
// warning, never an exception.
#include <gtest/gtest.h>

#include <fstream>

#include "io_test_util.h"
#include "shellflow/io/plot_runner.h"

namespace shellflow::io {
namespace {

using test::LogCapture;

void write_probes_csv(const std::filesystem::path& file, int probes) {
  std::ofstream out(file);
  out << "time";
  for (int p = 0; p < probes; ++p) out << ",w_" << p;
  out << "\n";
  for (int row = 0; row < 4; ++row) {
    out << 0.01 * row;
    for (int p = 0; p < probes; ++p) out << "," << 0.001 * (row + 1) * (p + 1);
    out << "\n";
  }
}

std::uintmax_t size_of(const std::filesystem::path& file) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  return ec ? 0 : size;
}

TEST(PlotRunner, DrawsEveryJobInOneProcess) {
  const test::TempDir dir("plot-runner");
  write_probes_csv(dir / "probes.csv", 3);
  write_probes_csv(dir / "many.csv", 20);  // the grid layout
  LogCapture log;
  PlotRunner runner(SHELLFLOW_PYTHON);
  runner.add("plot_probes.py", {(dir / "probes.csv").string(), "-o", (dir / "probes.png").string()});
  runner.add("plot_probes.py", {(dir / "many.csv").string(), "-o", (dir / "many dir -o.png").string()});
  EXPECT_EQ(runner.size(), 2u);
  EXPECT_TRUE(runner.run());
  EXPECT_EQ(runner.size(), 0u);
  EXPECT_GT(size_of(dir / "probes.png"), 1000u);
  EXPECT_GT(size_of(dir / "many dir -o.png"), 1000u);
  EXPECT_EQ(log.text().find("plot failed"), std::string::npos) << log.text();
}

TEST(PlotRunner, FailingJobIsAWarningAndTheOthersAreDrawn) {
  const test::TempDir dir("plot-runner-fail");
  write_probes_csv(dir / "probes.csv", 2);
  LogCapture log;
  PlotRunner runner(SHELLFLOW_PYTHON);
  runner.add("plot_probes.py", {(dir / "missing.csv").string(), "-o", (dir / "missing.png").string()});
  runner.add("plot_probes.py", {(dir / "probes.csv").string(), "-o", (dir / "probes.png").string()});
  bool ok = true;
  EXPECT_NO_THROW(ok = runner.run());
  EXPECT_FALSE(ok);
  EXPECT_NE(log.text().find("plot failed"), std::string::npos) << log.text();
  EXPECT_NE(log.text().find("the numerical output is complete"), std::string::npos) << log.text();
  EXPECT_GT(size_of(dir / "probes.png"), 1000u);
  EXPECT_FALSE(std::filesystem::exists(dir / "missing.png"));
}

TEST(PlotRunner, MissingScriptOrPythonIsAWarning) {
  LogCapture log;
  PlotRunner no_script(SHELLFLOW_PYTHON);
  no_script.add("plot_nothing_such.py", {});
  EXPECT_EQ(no_script.size(), 0u);
  EXPECT_TRUE(no_script.run());
  EXPECT_NE(log.text().find("plot skipped"), std::string::npos) << log.text();

  const test::TempDir dir("plot-runner-nopython");
  write_probes_csv(dir / "probes.csv", 1);
  PlotRunner no_python(dir / "no-python");
  no_python.add("plot_probes.py", {(dir / "probes.csv").string()});
  bool ok = true;
  EXPECT_NO_THROW(ok = no_python.run());
  EXPECT_FALSE(ok);
  EXPECT_NE(log.text().find("cannot start"), std::string::npos) << log.text();
}

}  // namespace
}  // namespace shellflow::io
