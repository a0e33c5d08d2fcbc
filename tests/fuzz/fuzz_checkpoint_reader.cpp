// Fuzz target: the checkpoint reader (io::parse_checkpoint, the checks of read_checkpoint on a
// file's bytes: signature, format, sizes, checksum, header and its sense) and the comparison
// with the current run (io::checkpoint_mismatch), whose messages quote the header's strings.
//
// The checksum is no signature: anyone can write a checkpoint with a valid one. So that the
// fuzzer reaches the header and its checks past the checksum, every input whose sizes fit
// gets its checksum recomputed, as a crafted checkpoint would have it.
//
// A shellflow::Error is the expected answer, and its message must be one line without control
// bytes; any other exception, a crash, a hang or a sanitizer report is a finding.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>

#include "fuzz_util.h"
#include "shellflow/core/archive.h"
#include "shellflow/core/error.h"
#include "shellflow/io/checkpoint.h"

namespace {

constexpr std::string_view kMagic = "shellflow checkpoint\n";
constexpr std::size_t kSizes = kMagic.size() + 4, kSum = kSizes + 16, kPrefix = kSum + 8;

/// Writes the checksum the sizes of `bytes` call for (io/checkpoint.h's layout).
void recompute_checksum(std::string& bytes) {
  if (bytes.size() < kPrefix) return;
  std::uint64_t header = 0, payload = 0;
  std::memcpy(&header, bytes.data() + kSizes, 8);
  std::memcpy(&payload, bytes.data() + kSizes + 8, 8);
  const std::uint64_t body = bytes.size() - kPrefix;
  if (header > body || payload != body - header) return;
  const std::string_view rest = std::string_view(bytes).substr(kPrefix);
  const std::string_view head = rest.substr(0, header), tail = rest.substr(header);
  const std::uint64_t sum =
      shellflow::checksum64(std::as_bytes(std::span(tail.data(), tail.size())),
                            shellflow::checksum64(std::as_bytes(std::span(head.data(), head.size()))));
  std::memcpy(bytes.data() + kSum, &sum, 8);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace shellflow;
  std::string bytes(reinterpret_cast<const char*>(data), size);
  recompute_checksum(bytes);
  try {
    const io::Checkpoint c = io::parse_checkpoint(bytes, "out/checkpoint_000010.ckpt");
    io::CheckpointHeader now;
    now.program_version = "0";
    now.case_name = "fuzz";
    now.digests = {{"shell", 1}, {"time", 2}, {"mesh shell", 3}};
    const std::string why = io::checkpoint_mismatch(c, now);
    fuzz::require_one_line(why.c_str());
  } catch (const Error& e) {
    fuzz::require_one_line(e.what());
  }
  return 0;
}
