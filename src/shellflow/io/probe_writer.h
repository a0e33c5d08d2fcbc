#pragma once
// Probe histories as CSV: one header line `time,<name1>,<name2>,...`, then one row per
// `append`, every number with 17 significant digits (round-trips a double exactly). Each
// row is flushed as soon as it is written, so the file is readable while the run goes on
// and after it dies.
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "shellflow/core/archive.h"
#include "shellflow/core/output_file.h"

namespace shellflow::io {

/// How an output writer starts: a new file, or (a restarted run) the file of the run it
/// continues, left as it is until restore() puts it back to the checkpoint's position.
enum class OutputMode { create, resume };

class ProbeWriter {
 public:
  /// Creates (or truncates) `path`, creating its directory, and writes the header; with
  /// OutputMode::resume it touches nothing until restore(). Throws shellflow::InputError
  /// when a name is empty, equals "time", contains a comma, a double quote or a control
  /// character (line break, tab, ...), starts or ends with a space, or is given twice;
  /// shellflow::Error when the file cannot be written.
  ProbeWriter(std::filesystem::path path, std::vector<std::string> names, OutputMode mode = OutputMode::create);

  /// Checkpoint: the file's length and rows. restore() cuts the file back to that length
  /// (the rows written after the checkpoint go; they are written again) and appends from
  /// there. Throws Error when the file is missing, shorter than at the checkpoint, or has
  /// another header.
  void save(ArchiveWriter& out) const;
  void restore(ArchiveReader& in);

  /// Writes the row `time,values[0],values[1],...` and flushes it. Throws shellflow::Error
  /// when `values` does not hold one value per name, when `time` is not finite, or when
  /// the write fails. Values that are NaN or infinite are written as `nan`, `inf`, `-inf`.
  void append(double time, std::span<const double> values);

  const std::filesystem::path& path() const { return path_; }
  const std::vector<std::string>& names() const { return names_; }
  /// Rows written so far (not counting the header).
  std::size_t rows() const { return rows_; }

 private:
  std::filesystem::path path_;
  std::vector<std::string> names_;
  AppendFile out_;  // never through a link (core/output_file.h)
  std::size_t rows_ = 0;
  std::uint64_t bytes_ = 0;  ///< the file's length
};

}  // namespace shellflow::io
