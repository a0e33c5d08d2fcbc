// core/output_file.h: no write through a symbolic link, one process per output folder.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "shellflow/core/error.h"
#include "shellflow/core/output_file.h"

namespace shellflow {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class OutputFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("shellflow_output_file_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "out");
    victim_ = dir_ / "victim.txt";
    std::ofstream(victim_) << "keep me";
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_, victim_;
};

TEST_F(OutputFile, AtomicWriteReplacesALinkInsteadOfWritingThroughIt) {
  const fs::path out = dir_ / "out" / "probes.csv";
  fs::create_symlink(victim_, out);
  write_file_atomically(out, "time,w\n");
  EXPECT_EQ(slurp(victim_), "keep me");
  EXPECT_FALSE(fs::is_symlink(out));
  EXPECT_EQ(slurp(out), "time,w\n");
}

TEST_F(OutputFile, AtomicWriteNeverFollowsALinkedTemporary) {
  const fs::path out = dir_ / "out" / "shell.pvd";
  fs::create_symlink(victim_, fs::path(out.string() + ".tmp"));  // planted where the temporary goes
  write_file_atomically(out, [](std::ostream& os) { os << "<VTKFile/>"; });
  EXPECT_EQ(slurp(victim_), "keep me");
  EXPECT_EQ(slurp(out), "<VTKFile/>");
  EXPECT_FALSE(fs::exists(fs::symlink_status(fs::path(out.string() + ".tmp"))));
}

TEST_F(OutputFile, SyncedWriteConcatenatesItsParts) {
  const fs::path out = dir_ / "out" / "checkpoint_000001.ckpt";
  write_file_atomically_synced(out, {"ab", "", "cd"});
  EXPECT_EQ(slurp(out), "abcd");
}

TEST_F(OutputFile, AppendFileRefusesALinkNamingIt) {
  const fs::path out = dir_ / "out" / "coupling.csv";
  fs::create_symlink(victim_, out);
  for (const auto mode : {AppendFile::Mode::truncate, AppendFile::Mode::append}) {
    try {
      AppendFile f(out, mode);
      FAIL() << "opened a link";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("is a symbolic link (to " + victim_.string() + ")"), std::string::npos)
          << e.what();
    }
  }
  EXPECT_EQ(slurp(victim_), "keep me");
}

TEST_F(OutputFile, AppendFileAppendsReadsAndCutsBack) {
  const fs::path out = dir_ / "out" / "probes.csv";
  {
    AppendFile f(out, AppendFile::Mode::truncate);
    f.write("time\n");
    f.write("1\n");
  }
  AppendFile f(out, AppendFile::Mode::append);
  EXPECT_EQ(f.size(), 7u);
  EXPECT_EQ(f.read_at(0, 5), "time\n");
  f.truncate(5);
  f.write("2\n");
  EXPECT_EQ(slurp(out), "time\n2\n");
  EXPECT_THROW(AppendFile(dir_ / "out" / "missing.csv", AppendFile::Mode::append), Error);  // append: not created
}

TEST_F(OutputFile, PrivateTemporaryIsNewAndKeepsTheExtension) {
  const fs::path a = private_temporary(dir_ / "out", "fluid", ".msh");
  const fs::path b = private_temporary(dir_ / "out", "fluid", ".msh");
  EXPECT_NE(a, b);
  EXPECT_EQ(a.extension(), ".msh");
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(a)));
  EXPECT_EQ(fs::file_size(a), 0u);
  rename_into_place(a, dir_ / "out" / "fluid.msh");
  EXPECT_TRUE(fs::exists(dir_ / "out" / "fluid.msh"));
  EXPECT_FALSE(fs::exists(a));
}

TEST_F(OutputFile, OneLockPerFolderNamesTheHolder) {
  std::optional<OutputLock> first(std::in_place, dir_ / "out");
  try {
    OutputLock second(dir_ / "out");  // another open file description: flock refuses it as for another process
    FAIL() << "two locks on one folder";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(fmt::format("(pid {})", ::getpid())), std::string::npos) << e.what();
  }
  first.reset();
  EXPECT_NO_THROW(OutputLock again(dir_ / "out"));  // released with its holder
}

TEST_F(OutputFile, LockFileThatIsALinkIsRefused) {
  fs::create_symlink(victim_, dir_ / "out" / OutputLock::kFileName);
  EXPECT_THROW(OutputLock lock(dir_ / "out"), Error);
  EXPECT_EQ(slurp(victim_), "keep me");
}

TEST_F(OutputFile, HardLinkedLockAndCsvAreRefusedAndTheirTargetKept) {
  fs::create_hard_link(victim_, dir_ / "out" / OutputLock::kFileName);
  try {
    OutputLock lock(dir_ / "out");
    FAIL() << "locked through a hard link";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is a hard link (2 names"), std::string::npos) << e.what();
  }
  fs::create_hard_link(victim_, dir_ / "out" / "probes.csv");
  for (const auto mode : {AppendFile::Mode::truncate, AppendFile::Mode::append})
    EXPECT_THROW(AppendFile(dir_ / "out" / "probes.csv", mode), Error);
  EXPECT_EQ(slurp(victim_), "keep me");
}

TEST_F(OutputFile, ARowThatDoesNotFitIsCutBackToTheLastWholeRow) {
  const fs::path out = dir_ / "out" / "probes.csv";
  AppendFile f(out, AppendFile::Mode::truncate);
  f.write("time,p\n");
  f.write("0,1\n");
  // A file size limit 3 bytes past the end makes the next write(2) partial, then EFBIG:
  // the way a disk that fills up mid-row behaves.
  rlimit before{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &before), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = before;
  small.rlim_cur = 11 + 3;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  bool threw = false;
  try {
    f.write("0.5,2.25\n");
  } catch (const Error& e) {
    threw = true;
    EXPECT_NE(std::string(e.what()).find("disk full?"), std::string::npos) << e.what();
  }
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &before), 0);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_TRUE(threw);
  EXPECT_EQ(slurp(out), "time,p\n0,1\n");
  f.write("1,3\n");  // the next row follows the last whole one
  EXPECT_EQ(slurp(out), "time,p\n0,1\n1,3\n");
}

}  // namespace
}  // namespace shellflow
