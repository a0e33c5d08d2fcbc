#include "shellflow/io/pvd_writer.h"

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <fstream>
#include <iterator>
#include <ostream>

#include "shellflow/core/error.h"
#include "shellflow/core/output_file.h"
#include "shellflow/io/vtu_writer.h"

namespace shellflow::io {

PvdWriter::PvdWriter(std::filesystem::path dir, std::string basename, OutputMode mode) {
  if (basename.empty() || basename.find('/') != std::string::npos || basename.find('\\') != std::string::npos) {
    throw_input_error(
        "output name '{}' must be a non-empty file name without '/' (in "
        "directory {})",
        basename, dir.string());
  }
  path_ = std::move(dir) / (std::move(basename) + ".pvd");
  if (mode == OutputMode::create) write();
}

void PvdWriter::save(ArchiveWriter& out) const {
  out.put(static_cast<std::uint64_t>(entries_.size()));
  for (const auto& e : entries_) {
    out.put(e.time);
    out.put(e.file);
    out.put(e.part);
  }
}

void PvdWriter::restore(ArchiveReader& in) {
  const auto n = in.get<std::uint64_t>();
  if (n > in.remaining() / 20) throw Error(in.what() + ": damaged collection entries");
  std::vector<Entry> entries(static_cast<std::size_t>(n));
  for (auto& e : entries) {
    e.time = in.get<double>();
    e.file = in.get_string();
    e.part = in.get<int>();
    // A series lists files of its own folder only (no path, no link out of it).
    const std::filesystem::path file(e.file);
    if (e.file.empty() || file.filename() != file || e.file == "." || e.file == ".." || !std::isfinite(e.time) ||
        e.part < 0)
      throw Error(fmt::format("{}: damaged (entry '{}' at t = {} of {} is not a file of the output folder)", in.what(),
                              printable(e.file), e.time, path_.filename().string()));
  }
  entries_ = std::move(entries);
  // Rewritten only when it differs from the checkpoint's series: a restart refused later
  // leaves the folder untouched.
  std::ifstream in_file(path_, std::ios::binary);
  const std::string now((std::istreambuf_iterator<char>(in_file)), std::istreambuf_iterator<char>());
  if (!in_file.bad() && !std::filesystem::is_symlink(path_) && now == xml()) return;
  write();
}

void PvdWriter::add(double time, const std::string& vtu_relative_path, int part) {
  if (!std::isfinite(time)) {
    throw Error(fmt::format("{}: time {} of dataset '{}' is not finite", path_.string(), time, vtu_relative_path));
  }
  if (part < 0) {
    throw Error(fmt::format("{}: dataset '{}' has negative part {}", path_.string(), vtu_relative_path, part));
  }
  if (vtu_relative_path.empty() || std::filesystem::path(vtu_relative_path).is_absolute()) {
    throw Error(fmt::format("{}: dataset path '{}' must be relative to the .pvd's directory", path_.string(),
                            vtu_relative_path));
  }
  bool replaced = false;
  for (auto& e : entries_) {
    if (e.time == time && e.part == part) {
      e.file = vtu_relative_path;
      replaced = true;
    }
  }
  if (!replaced) entries_.push_back({time, vtu_relative_path, part});
  write();
}

std::string PvdWriter::xml() const {
  std::string xml;
  xml += "<?xml version=\"1.0\"?>\n";
  xml += fmt::format("<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"{}\">\n",
                     std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian");
  xml += "  <Collection>\n";
  for (const auto& e : entries_) {
    xml += fmt::format("    <DataSet timestep=\"{:.17g}\" group=\"\" part=\"{}\" file=\"{}\"/>\n", e.time, e.part,
                       xml_escape(e.file));
  }
  xml += "  </Collection>\n";
  xml += "</VTKFile>\n";
  return xml;
}

void PvdWriter::write() const { write_file_atomically(path_, xml()); }

}  // namespace shellflow::io
