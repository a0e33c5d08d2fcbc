// Checkpoint files (io/checkpoint.h) and the output writers' checkpoint positions: a round
// trip keeps every bit; a truncated, damaged or foreign file is refused with its own
// message; the two newest checkpoints are kept; the case digests name the section that
// changed; a restored CSV or PVD continues as if the run had not stopped.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "io_test_util.h"
#include "shellflow/core/archive.h"
#include "shellflow/core/error.h"
#include "shellflow/io/checkpoint.h"
#include "shellflow/io/probe_writer.h"
#include "shellflow/io/pvd_writer.h"

namespace shellflow::io {
namespace {

using test::TempDir;

std::string read_all(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_all(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc) << bytes;
}

/// The message of the Error `f` throws (fails when it throws none).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return {};
}

CheckpointHeader header(long step) {
  CheckpointHeader h;
  h.program_version = "1.2.3";
  h.build = 42;
  h.case_name = "panel";
  h.step = step;
  h.time = 1e-4 * double(step);
  h.threads = 2;
  h.simd = "avx2";
  h.digests = {{"shell", 7}, {"mesh shell", 9}};
  return h;
}

std::string payload() {
  ArchiveWriter out;
  out.put(std::vector<double>{0.1, -0.0, std::numeric_limits<double>::denorm_min(),
                              std::numeric_limits<double>::quiet_NaN(), 1.0 / 3.0});
  out.put(std::vector<Vec3>{Vec3(1, 2, 3), Vec3(-1e300, 5e-324, 0.5)});
  out.put(std::string("coupled"));
  out.put(long{123456789012});
  out.put(true);
  return out.take();
}

TEST(Archive, EveryValueComesBackWithTheSameBits) {
  const std::string bytes = payload();
  ArchiveReader in(bytes, "test");
  const auto v = in.get_vector<double>();
  ASSERT_EQ(v.size(), 5u);
  EXPECT_TRUE(std::signbit(v[1]));
  EXPECT_EQ(v[2], std::numeric_limits<double>::denorm_min());
  EXPECT_TRUE(std::isnan(v[3]));
  EXPECT_EQ(v[4], 1.0 / 3.0);
  const auto x = in.get_vec3s();
  ASSERT_EQ(x.size(), 2u);
  EXPECT_EQ(x[1], Vec3(-1e300, 5e-324, 0.5));
  EXPECT_EQ(in.get_string(), "coupled");
  EXPECT_EQ(in.get<long>(), 123456789012);
  EXPECT_TRUE(in.get<bool>());
  EXPECT_EQ(in.remaining(), 0u);
  in.expect_end();
}

TEST(Archive, ReadingPastTheEndOrAnImpossibleSizeIsAnError) {
  ArchiveWriter out;
  out.put(std::uint64_t{1} << 60);  // a "vector" of 2^60 doubles in 8 bytes
  ArchiveReader in(out.bytes(), "short.ckpt");
  EXPECT_NE(error_of([&] { in.get_vector<double>(); }).find("short.ckpt"), std::string::npos);
  ArchiveReader empty(std::string_view{}, "empty");
  EXPECT_NE(error_of([&] { empty.get<double>(); }).find("ends early"), std::string::npos);
}

TEST(Archive, ChecksumSeesEveryByte) {
  std::string bytes = payload();
  const std::uint64_t sum = checksum64(bytes);
  for (std::size_t i = 0; i < bytes.size(); i += 7) {
    std::string changed = bytes;
    changed[i] = static_cast<char>(changed[i] ^ 0x10);
    EXPECT_NE(checksum64(changed), sum) << "byte " << i;
  }
  EXPECT_NE(checksum64(bytes + '\0'), sum);  // the length counts
}

TEST(Checkpoint, RoundTripKeepsHeaderAndPayload) {
  TempDir dir("ckpt");
  const std::string p = payload();
  const auto bytes = write_checkpoint(dir.path(), header(120), p);
  const auto file = checkpoint_path(dir.path(), 120);
  EXPECT_EQ(file.filename(), "checkpoint_000120.ckpt");
  EXPECT_EQ(std::filesystem::file_size(file), bytes);
  EXPECT_FALSE(std::filesystem::exists(file.string() + ".tmp"));
  const Checkpoint c = read_checkpoint(file);
  EXPECT_EQ(c.payload, p);
  EXPECT_EQ(c.header.program_version, "1.2.3");
  EXPECT_EQ(c.header.build, 42u);
  EXPECT_EQ(c.header.case_name, "panel");
  EXPECT_EQ(c.header.step, 120);
  EXPECT_EQ(c.header.time, 1e-4 * 120);
  EXPECT_EQ(c.header.threads, 2);
  EXPECT_EQ(c.header.simd, "avx2");
  EXPECT_EQ(c.header.digests, header(120).digests);
  EXPECT_EQ(find_checkpoint(dir.path()), file);
}

TEST(Checkpoint, TheTwoNewestAreKeptAndTheDirectoryGivesTheNewest) {
  TempDir dir("ckpt-keep");
  write_all(dir / "checkpoint_000050.ckpt.tmp", "left by a kill");
  for (long step : {10, 20, 30, 40}) write_checkpoint(dir.path(), header(step), payload());
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) names.push_back(e.path().filename());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"checkpoint_000030.ckpt", "checkpoint_000040.ckpt"}));
  EXPECT_EQ(find_checkpoint(dir.path()), checkpoint_path(dir.path(), 40));
  EXPECT_EQ(find_checkpoint(checkpoint_path(dir.path(), 30)), checkpoint_path(dir.path(), 30));
  TempDir none("ckpt-none");
  EXPECT_NE(error_of([&] { find_checkpoint(none.path()); }).find("no checkpoint_NNNNNN.ckpt"), std::string::npos);
}

TEST(Checkpoint, AHugeFileNamedLikeACheckpointIsRefusedBeforeItIsRead) {
  // 64 GiB (sparse): refused from its first bytes and its size, without reading it whole.
  TempDir dir("ckpt-huge");
  const auto file = checkpoint_path(dir.path(), 300);
  write_all(file, "not a checkpoint");
  std::filesystem::resize_file(file, std::uintmax_t{64} << 30);
  EXPECT_NE(error_of([&] { read_checkpoint(file); }).find("not a shellflow checkpoint"), std::string::npos);
  // A real checkpoint's signature and sizes, with 64 GiB appended: refused by its size.
  write_checkpoint(dir.path(), header(300), payload());
  const auto good_size = std::filesystem::file_size(file);
  std::filesystem::resize_file(file, good_size + (std::uintmax_t{64} << 30));
  EXPECT_NE(error_of([&] { read_checkpoint(file); }).find("bytes after the end of the checkpoint"), std::string::npos);
}

TEST(Checkpoint, TruncatedDamagedForeignAndMissingFilesEachGetTheirMessage) {
  TempDir dir("ckpt-bad");
  write_checkpoint(dir.path(), header(7), payload());
  const auto file = checkpoint_path(dir.path(), 7);
  const std::string good = read_all(file);
  // Truncated anywhere: in the signature, the sizes, the header, the payload.
  for (std::size_t keep : {std::size_t{5}, std::size_t{30}, std::size_t{60}, good.size() - 1}) {
    write_all(file, good.substr(0, keep));
    const std::string e = error_of([&] { read_checkpoint(file); });
    EXPECT_TRUE(e.find("truncated") != std::string::npos || e.find("not a shellflow checkpoint") != std::string::npos)
        << keep << ": " << e;
    EXPECT_NE(e.find(file.string()), std::string::npos) << e;
  }
  // One bit flipped anywhere after the sizes.
  for (std::size_t at : {std::size_t{60}, good.size() / 2, good.size() - 1}) {
    std::string bad = good;
    bad[at] = static_cast<char>(bad[at] ^ 0x01);
    write_all(file, bad);
    EXPECT_NE(error_of([&] { read_checkpoint(file); }).find("checksum mismatch"), std::string::npos) << at;
  }
  write_all(file, good + "x");
  EXPECT_NE(error_of([&] { read_checkpoint(file); }).find("after the end"), std::string::npos);
  write_all(file, "time,w\n0,0\n");
  EXPECT_NE(error_of([&] { read_checkpoint(file); }).find("not a shellflow checkpoint"), std::string::npos);
  std::string other_format = good;
  other_format[21] = 9;  // the format number follows the 21-byte signature
  write_all(file, other_format);
  EXPECT_NE(error_of([&] { read_checkpoint(file); }).find("checkpoint format 9"), std::string::npos);
  EXPECT_NE(error_of([&] { read_checkpoint(dir / "checkpoint_000008.ckpt"); }).find("no such checkpoint"),
            std::string::npos);
}

TEST(Checkpoint, MismatchNamesTheVersionOrTheSectionsThatChanged) {
  Checkpoint c;
  c.file = "out/checkpoint_000007.ckpt";
  c.header = header(7);
  CheckpointHeader now = header(0);
  EXPECT_EQ(checkpoint_mismatch(c, now), "");
  now.build = 43;  // another build of the same version: allowed (a warning in the run)
  EXPECT_EQ(checkpoint_mismatch(c, now), "");
  now.program_version = "1.2.4";
  EXPECT_NE(checkpoint_mismatch(c, now).find("written by shellflow 1.2.3, this is shellflow 1.2.4"), std::string::npos);
  now = header(0);
  now.digests = {{"shell", 8}, {"mesh shell", 9}, {"coupling", 1}};
  const std::string why = checkpoint_mismatch(c, now);
  EXPECT_NE(why.find("sections: shell, coupling (added)"), std::string::npos) << why;
  EXPECT_EQ(why.find("mesh shell"), std::string::npos) << why;
}

TEST(CaseDigests, OnlyTheChangedSectionDiffersAndTheRestartableKeysAreLeftOut) {
  const auto digests = [](const std::string& text) { return case_digests(YAML::Load(text)); };
  const std::string base =
      "name: a\nshell: {thickness: 1.0e-3, material: {density: 2710}}\n"
      "time: {end: 0.1, step: 1.0e-4}\noutput: {every: 5}\nstudy: {parameter: mach}\n";
  const auto a = digests(base);
  ASSERT_EQ(a.size(), 4u);  // name, output, shell, time; not study
  const auto changed = [&](const std::string& text) {
    const auto b = digests(text);
    std::vector<std::string> names;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
      if (!(a[i] == b[i])) names.push_back(b[i].name);
    return names;
  };
  auto text = base;
  text.replace(text.find("1.0e-3"), 6, "1.1e-3");
  EXPECT_EQ(changed(text), std::vector<std::string>{"shell"});
  text = base;
  text.replace(text.find("end: 0.1"), 8, "end: 0.5");
  EXPECT_TRUE(changed(text).empty());
  text = base;
  text.replace(text.find("step: 1.0e-4"), 12, "step: 2.0e-4");
  EXPECT_EQ(changed(text), std::vector<std::string>{"time"});
  EXPECT_TRUE(changed(base + "\n").empty());
  text = base;
  text.replace(text.find("every: 5"), 8, "every: 5, checkpoint_every: 100, directory: elsewhere");
  EXPECT_TRUE(changed(text).empty());
  text = base;
  text.replace(text.find("mach"), 4, "density");
  EXPECT_TRUE(changed(text).empty());
}

TEST(ProbeWriterCheckpoint, ARestoredWriterCutsTheLaterRowsAndContinues) {
  TempDir dir("csv-ckpt");
  const auto file = dir / "probes.csv";
  ArchiveWriter at_two;
  {
    ProbeWriter w(file, {"a", "b"});
    w.append(0.0, std::vector<double>{1, 2});
    w.append(0.1, std::vector<double>{3, 4});
    w.save(at_two);
    w.append(0.2, std::vector<double>{5, 6});  // after the checkpoint: a killed run's row
  }
  const std::string uninterrupted = [&] {
    TempDir other("csv-straight");
    ProbeWriter w(other / "probes.csv", {"a", "b"});
    for (auto [t, a, b] : {std::tuple{0.0, 1, 2}, {0.1, 3, 4}, {0.2, 7, 8}})
      w.append(t, std::vector<double>{double(a), double(b)});
    return read_all(other / "probes.csv");
  }();
  ProbeWriter resumed(file, {"a", "b"}, OutputMode::resume);
  ArchiveReader in(at_two.bytes(), "t");
  resumed.restore(in);
  EXPECT_EQ(resumed.rows(), 2u);
  resumed.append(0.2, std::vector<double>{7, 8});
  EXPECT_EQ(read_all(file), uninterrupted);

  // A file shorter than at the checkpoint, or with other columns, is refused untouched.
  write_all(file, "time,a,b\n0,1,2\n");
  ProbeWriter shorter(file, {"a", "b"}, OutputMode::resume);
  ArchiveReader again(at_two.bytes(), "t");
  EXPECT_NE(error_of([&] { shorter.restore(again); }).find("fewer than the"), std::string::npos);
  EXPECT_EQ(read_all(file), "time,a,b\n0,1,2\n");
  write_all(file, uninterrupted);
  ProbeWriter other_columns(file, {"a", "c"}, OutputMode::resume);
  ArchiveReader third(at_two.bytes(), "t");
  EXPECT_NE(error_of([&] { other_columns.restore(third); }).find("header is not"), std::string::npos);
  EXPECT_EQ(read_all(file), uninterrupted);
}

TEST(PvdWriterCheckpoint, ARestoredCollectionDropsTheLaterFramesAndContinues) {
  TempDir dir("pvd-ckpt");
  ArchiveWriter saved;
  {
    PvdWriter w(dir.path(), "shell");
    w.add(0.0, "shell_000000.vtu");
    w.add(0.5, "shell_000005.vtu");
    w.save(saved);
    w.add(1.0, "shell_000010.vtu");
  }
  const std::string straight = [&] {
    TempDir other("pvd-straight");
    PvdWriter w(other.path(), "shell");
    w.add(0.0, "shell_000000.vtu");
    w.add(0.5, "shell_000005.vtu");
    w.add(1.0, "shell_000010.vtu");
    return read_all(other / "shell.pvd");
  }();
  const std::string before = read_all(dir / "shell.pvd");
  PvdWriter resumed(dir.path(), "shell", OutputMode::resume);
  EXPECT_EQ(read_all(dir / "shell.pvd"), before);  // untouched until restore
  ArchiveReader in(saved.bytes(), "t");
  resumed.restore(in);
  EXPECT_EQ(resumed.entries().size(), 2u);
  resumed.add(1.0, "shell_000010.vtu");
  EXPECT_EQ(read_all(dir / "shell.pvd"), straight);
}

}  // namespace
}  // namespace shellflow::io
