#include "shellflow/io/probe_writer.h"

#include <fmt/format.h>

#include <cmath>
#include <set>

#include "shellflow/core/error.h"

namespace shellflow::io {
namespace {

/// Why `name` cannot be a CSV column header, or nullptr when it can.
const char* name_problem(const std::string& name) {
  if (name.empty()) return "is empty";
  if (name == "time") return "is 'time', the name of the first column";
  for (char ch : name) {
    if (ch == ',') return "contains a comma";
    if (ch == '"') return "contains a double quote";
    if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f) {
      return "contains a line break or another control character";
    }
  }
  if (name.front() == ' ' || name.back() == ' ') return "starts or ends with a space";
  return nullptr;
}

std::string header_line(const std::vector<std::string>& names) {
  std::string header = "time";
  for (const auto& n : names) {
    header += ',';
    header += n;
  }
  header += '\n';
  return header;
}

std::string number(double x) {
  if (std::isnan(x)) return "nan";
  return fmt::format("{:.17g}", x);  // inf, -inf as such
}

}  // namespace

ProbeWriter::ProbeWriter(std::filesystem::path path, std::vector<std::string> names, OutputMode mode)
    : path_(std::move(path)), names_(std::move(names)) {
  std::set<std::string> seen;
  for (std::size_t i = 0; i < names_.size(); ++i) {
    const auto& n = names_[i];
    if (const char* why = name_problem(n)) {
      throw_input_error(
          "{}: probe {} name '{}' {}; probe names are CSV column headers: use letters, "
          "digits, '_', '-', '.' (no commas, quotes or line breaks)",
          path_.string(), i + 1, n, why);
    }
    if (!seen.insert(n).second) {
      throw_input_error("{}: probe name '{}' is given twice; give each probe its own name", path_.string(), n);
    }
  }

  if (mode == OutputMode::resume) return;
  out_ = AppendFile(path_, AppendFile::Mode::truncate);
  const std::string header = header_line(names_);
  out_.write(header);
  bytes_ = header.size();
}

void ProbeWriter::save(ArchiveWriter& out) const {
  out.put(bytes_);
  out.put(static_cast<std::uint64_t>(rows_));
}

void ProbeWriter::restore(ArchiveReader& in) {
  const auto bytes = in.get<std::uint64_t>();
  const auto rows = in.get<std::uint64_t>();
  if (!process_writes_files()) {  // a distributed run's other ranks: rank 0 continues the file
    out_ = AppendFile(path_, AppendFile::Mode::append);
    bytes_ = bytes;
    rows_ = rows;
    return;
  }
  // Opened first (never through a link), then measured, checked and cut back through that
  // descriptor.
  AppendFile file;
  try {
    file = AppendFile(path_, AppendFile::Mode::append);
  } catch (const Error& e) {
    throw Error(fmt::format("{}; the restart needs the output of the run it continues", e.what()));
  }
  const std::uint64_t size = file.size();
  if (size < bytes)
    throw Error(
        fmt::format("{}: {} bytes, fewer than the {} at the checkpoint; it was changed after the "
                    "checkpoint, so the run cannot be continued bit for bit",
                    path_.string(), size, bytes));
  const std::string header = header_line(names_);
  if (file.read_at(0, header.size()) != header)
    throw Error(fmt::format("{}: its header is not '{}'; it is not the output of this run", path_.string(),
                            header.substr(0, header.size() - 1)));
  if (size != bytes) file.truncate(bytes);  // untouched when it ends at the checkpoint
  out_ = std::move(file);
  bytes_ = bytes;
  rows_ = rows;
}

void ProbeWriter::append(double time, std::span<const double> values) {
  if (values.size() != names_.size()) {
    throw Error(fmt::format("{}: row at time {} has {} values for {} probes", path_.string(), time, values.size(),
                            names_.size()));
  }
  if (!std::isfinite(time)) {
    throw Error(fmt::format("{}: time {} is not finite", path_.string(), time));
  }
  std::string row = number(time);
  for (double v : values) {
    row += ',';
    row += number(v);
  }
  row += '\n';
  if (!out_.is_open()) throw Error(fmt::format("{}: not open (a resumed writer before restore)", path_.string()));
  out_.write(row);  // one write per row: a crash leaves whole rows
  ++rows_;
  bytes_ += row.size();
}

}  // namespace shellflow::io
