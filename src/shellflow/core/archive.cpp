#include "shellflow/core/archive.h"

namespace shellflow {

std::uint64_t checksum64(std::span<const std::byte> bytes, std::uint64_t seed) {
  constexpr std::uint64_t prime = 0x100000001b3ULL;
  std::uint64_t h = seed;
  std::size_t i = 0;
  for (; i + 8 <= bytes.size(); i += 8) {
    std::uint64_t word;
    std::memcpy(&word, bytes.data() + i, 8);
    h = (h ^ word) * prime;
    h ^= h >> 29;  // fold the high bits down: a word-wise FNV alone mixes them poorly
  }
  for (; i < bytes.size(); ++i) h = (h ^ std::to_integer<std::uint64_t>(bytes[i])) * prime;
  h ^= static_cast<std::uint64_t>(bytes.size());
  return h * prime;
}

void ArchiveWriter::put(const std::vector<Vec3>& values) {
  put(static_cast<std::uint64_t>(values.size()));
  for (const Vec3& x : values) bytes_.append(reinterpret_cast<const char*>(x.data()), 3 * sizeof(double));
}

std::vector<Vec3> ArchiveReader::get_vec3s() {
  const auto n = count(3 * sizeof(double));
  std::vector<Vec3> v(n);
  for (Vec3& x : v) std::memcpy(x.data(), take(3 * sizeof(double)), 3 * sizeof(double));
  return v;
}

const char* ArchiveReader::take(std::size_t n) {
  if (n > bytes_.size() - at_)
    throw Error(
        fmt::format("{}: ends early ({} bytes, {} more needed at byte {}); it is not a checkpoint of this "
                    "kind of run or it is damaged",
                    what_, bytes_.size(), n, at_));
  const char* p = bytes_.data() + at_;
  at_ += n;
  return p;
}

std::size_t ArchiveReader::count(std::size_t element) {
  const auto n = get<std::uint64_t>();
  if (element > 0 && n > (bytes_.size() - at_) / element)
    throw Error(
        fmt::format("{}: a stored size {} at byte {} exceeds the {} bytes left; it is not a checkpoint of "
                    "this kind of run or it is damaged",
                    what_, n, at_ - 8, bytes_.size() - at_));
  return static_cast<std::size_t>(n);
}

void ArchiveReader::expect_size(std::string_view item, std::size_t stored, std::size_t expected) const {
  if (stored != expected)
    throw Error(
        fmt::format("{}: {} has {} entries in the checkpoint, {} in this run; the checkpoint is of "
                    "another mesh or model",
                    what_, item, stored, expected));
}

void ArchiveReader::expect_end() const {
  if (at_ != bytes_.size())
    throw Error(
        fmt::format("{}: {} bytes left unread; the checkpoint is of another kind of run", what_, bytes_.size() - at_));
}

}  // namespace shellflow
