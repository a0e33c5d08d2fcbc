#pragma once
// A binary archive for checkpoints (io/checkpoint.h): values appended to a byte buffer in
// the machine's byte order, read back in the same order. Every solver, driver and output
// writer that a run's next step reads saves itself into one (its `save(ArchiveWriter&)`)
// and restores itself from one (`restore(ArchiveReader&)`), so that a restarted run repeats
// the uninterrupted one bit for bit. Doubles are stored as their bits: nothing is rounded.
//
// Each value is preceded by nothing: the order is the format. A reader that runs past the
// end, or finds a size that cannot be (a vector longer than the bytes left), throws
// shellflow::Error naming the archive; readers of fixed-size objects check the sizes they
// expect with expect_size().
#include <Eigen/Core>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "shellflow/core/error.h"
#include "shellflow/core/types.h"

namespace shellflow {

/// 64-bit FNV-1a over the bytes taken 8 at a time (a corruption check, not a cryptographic
/// hash): fast enough to check a checkpoint of tens of MB in milliseconds.
std::uint64_t checksum64(std::span<const std::byte> bytes, std::uint64_t seed = 0xcbf29ce484222325ULL);
inline std::uint64_t checksum64(std::string_view text) {
  return checksum64(std::as_bytes(std::span(text.data(), text.size())));
}

class ArchiveWriter {
 public:
  template <class T>
  requires std::is_trivially_copyable_v<T>
  void put(const T& value) {
    const auto* p = reinterpret_cast<const char*>(&value);
    bytes_.append(p, sizeof(T));
  }
  void put(std::string_view s) {
    put(static_cast<std::uint64_t>(s.size()));
    bytes_.append(s.data(), s.size());
  }
  void put(const std::string& s) { put(std::string_view(s)); }
  void put(const char* s) { put(std::string_view(s)); }
  template <class T>
  requires std::is_trivially_copyable_v<T>
  void put_span(std::span<const T> values) {
    put(static_cast<std::uint64_t>(values.size()));
    bytes_.append(reinterpret_cast<const char*>(values.data()), values.size_bytes());
  }
  template <class T>
  requires std::is_trivially_copyable_v<T>
  void put(const std::vector<T>& values) { put_span(std::span<const T>(values)); }
  void put(const std::vector<Vec3>& values);
  void put(const Eigen::VectorXd& v) { put_span(std::span<const double>(v.data(), std::size_t(v.size()))); }
  void put(const std::vector<std::string>& values) {
    put(static_cast<std::uint64_t>(values.size()));
    for (const auto& s : values) put(s);
  }

  const std::string& bytes() const { return bytes_; }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

class ArchiveReader {
 public:
  /// `what` names the archive in messages (e.g. the checkpoint file).
  ArchiveReader(std::string_view bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}

  template <class T>
  requires std::is_trivially_copyable_v<T> T get() {
    T value;
    std::memcpy(&value, take(sizeof(T)), sizeof(T));
    return value;
  }
  std::string get_string() {
    const auto n = count(1);
    return std::string(take(n), n);
  }
  template <class T>
  requires std::is_trivially_copyable_v<T> std::vector<T> get_vector() {
    const auto n = count(sizeof(T));
    std::vector<T> v(n);
    if (n > 0) std::memcpy(v.data(), take(n * sizeof(T)), n * sizeof(T));
    return v;
  }
  std::vector<Vec3> get_vec3s();
  Eigen::VectorXd get_eigen() {
    const auto v = get_vector<double>();
    return Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
  }
  /// Throws Error "`what`: `item` has N entries, this run has M" when they differ.
  void expect_size(std::string_view item, std::size_t stored, std::size_t expected) const;
  /// Throws unless every byte was read (a checkpoint of another kind of run).
  void expect_end() const;
  std::size_t remaining() const { return bytes_.size() - at_; }
  const std::string& what() const { return what_; }

 private:
  const char* take(std::size_t n);
  /// A stored element count, checked against the bytes left (`element` bytes each).
  std::size_t count(std::size_t element);

  std::string_view bytes_;
  std::size_t at_ = 0;
  std::string what_;
};

}  // namespace shellflow
