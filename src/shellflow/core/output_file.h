#pragma once
// Files written into an output folder without following symbolic links (docs/output.md,
// "What a run may write"). A case bundle may ship `results/probes.csv -> ~/.bashrc`: no
// writer here ever writes through such a link, and none removes anything but a regular file.
//
// - write_file_atomically: a fresh temporary `<path>.tmp` (an old one unlinked first, then
//   created with O_CREAT | O_EXCL | O_NOFOLLOW, so it is a new regular file of this process),
//   filled, then renamed over `<path>` (rename replaces a link named `<path>` instead of
//   writing through it).
// - AppendFile: a file written row by row (probes.csv), opened with O_NOFOLLOW.
// - private_temporary: a new, empty file of this process for a writer that opens files by
//   name itself (Gmsh), then renamed into place.
// - OutputLock: one process per output folder (flock on `.shellflow.lock`).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

namespace shellflow {

/// Whether this process writes files (true unless set): on the ranks of a distributed run other
/// than rank 0 it is false, and every writer here does nothing (an AppendFile is not opened and
/// takes the rows without writing them), so that the code of a run is the same on every rank
/// and only rank 0 touches the output folder. PieceOutput lifts it for the files every rank
/// writes itself (its `.vtu` piece of a frame).
bool process_writes_files();
void set_process_writes_files(bool writes);
/// While it lives, this process writes files whatever set_process_writes_files says.
class PieceOutput {
 public:
  PieceOutput();
  ~PieceOutput();
  PieceOutput(const PieceOutput&) = delete;
  PieceOutput& operator=(const PieceOutput&) = delete;

 private:
  bool before_;
};

/// Writes `path` whole from `fill` (see above); throws Error naming the file when it cannot,
/// or when `path` is a symbolic link to a folder (rename cannot replace that).
void write_file_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& fill);
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);
/// The same from `parts` in order, flushed to disk (fsync) before the rename: checkpoints.
void write_file_atomically_synced(const std::filesystem::path& path, const std::vector<std::string_view>& parts);

/// The one-line error for an output name that is a symbolic link.
std::string link_refusal(const std::filesystem::path& path);

/// A file written by appending (rows of a CSV), never through a link.
class AppendFile {
 public:
  enum class Mode { truncate, append };  ///< append: an existing file (a restart's), not created
  AppendFile() = default;
  AppendFile(const std::filesystem::path& path, Mode mode);
  AppendFile(AppendFile&& o) noexcept;
  AppendFile& operator=(AppendFile&& o) noexcept;
  AppendFile(const AppendFile&) = delete;
  AppendFile& operator=(const AppendFile&) = delete;
  ~AppendFile();
  bool is_open() const { return fd_ >= 0 || discard_; }
  /// Writes all of `bytes` (one write(2) call for a short row: a crash leaves whole rows);
  /// when it cannot (a full disk), cuts the file back to its size before and throws Error.
  void write(std::string_view bytes);
  /// Its size in bytes, up to `n` bytes from `offset`, and cutting it back to `size` bytes
  /// (a restart continuing the file).
  std::uint64_t size() const;
  std::string read_at(std::uint64_t offset, std::size_t n) const;
  void truncate(std::uint64_t size);

 private:
  int fd_ = -1;
  bool discard_ = false;  ///< made while the process writes no files: rows are dropped
  std::filesystem::path path_;
};

/// Creates `dir/<stem>.XXXXXX<extension>`, a new empty regular file of this process
/// (mkstemps), and returns its path: for writers that open files by name and pick the format
/// by the extension (Gmsh), renamed into place after.
std::filesystem::path private_temporary(const std::filesystem::path& dir, const std::string& stem,
                                        const std::string& extension);
/// Renames `from` over `to` (same folder); removes `from` and throws Error when it cannot.
void rename_into_place(const std::filesystem::path& from, const std::filesystem::path& to);

/// Holds `dir/.shellflow.lock` locked (flock, LOCK_EX) while it lives; the file holds the
/// holder's pid. A second process gets one line naming the folder and that pid. The lock
/// goes with the process (also when it is killed); the descriptor is not inherited by the
/// programs a run starts. On a file system without locks (ENOLCK, EOPNOTSUPP) it warns and
/// holds nothing.
class OutputLock {
 public:
  static constexpr const char* kFileName = ".shellflow.lock";
  OutputLock() = default;
  explicit OutputLock(const std::filesystem::path& dir);
  OutputLock(OutputLock&& o) noexcept;
  OutputLock& operator=(OutputLock&& o) noexcept;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  ~OutputLock();

 private:
  int fd_ = -1;
};

}  // namespace shellflow
