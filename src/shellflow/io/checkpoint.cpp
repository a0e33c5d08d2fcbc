#include "shellflow/io/checkpoint.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>

#include "shellflow/core/error.h"
#include "shellflow/core/output_file.h"
#include "shellflow/io/case.h"  // kMaxSteps
#include "shellflow/mesh/mesh.h"

namespace shellflow::io {
namespace fs = std::filesystem;
namespace {

constexpr std::string_view kMagic = "shellflow checkpoint\n";
constexpr std::size_t kPrefix = kMagic.size() + 4 + 3 * 8;

/// The step of a checkpoint file name, or nullopt.
std::optional<long> checkpoint_step(std::string_view name) {
  constexpr std::string_view head = "checkpoint_", tail = ".ckpt";
  if (!name.starts_with(head) || !name.ends_with(tail)) return std::nullopt;
  const std::string_view digits = name.substr(head.size(), name.size() - head.size() - tail.size());
  if (digits.size() < 6 || digits.size() > 18) return std::nullopt;
  long step = 0;
  for (const char c : digits) {
    if (c < '0' || c > '9') return std::nullopt;
    step = 10 * step + (c - '0');
  }
  return step;
}

/// The complete checkpoints of `dir` by step.
std::map<long, fs::path> checkpoints_in(const fs::path& dir) {
  std::map<long, fs::path> found;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->symlink_status(ec).type() != fs::file_type::regular) continue;
    if (const auto step = checkpoint_step(it->path().filename().string())) found[*step] = it->path();
  }
  return found;
}

void put_header(ArchiveWriter& out, const CheckpointHeader& h) {
  out.put(h.program_version);
  out.put(h.build);
  out.put(h.case_name);
  out.put(h.step);
  out.put(h.time);
  out.put(h.threads);
  out.put(h.simd);
  out.put(static_cast<std::uint64_t>(h.digests.size()));
  for (const auto& d : h.digests) {
    out.put(d.name);
    out.put(d.digest);
  }
}

CheckpointHeader get_header(ArchiveReader& in) {
  CheckpointHeader h;
  h.program_version = in.get_string();
  h.build = in.get<std::uint64_t>();
  h.case_name = in.get_string();
  h.step = in.get<long>();
  h.time = in.get<double>();
  h.threads = in.get<int>();
  h.simd = in.get_string();
  const auto n = in.get<std::uint64_t>();
  if (n > in.remaining() / 16) throw Error(in.what() + ": damaged header (digest count)");
  for (std::uint64_t k = 0; k < n; ++k) {
    SectionDigest d;
    d.name = in.get_string();
    d.digest = in.get<std::uint64_t>();
    h.digests.push_back(std::move(d));
  }
  in.expect_end();
  return h;
}

}  // namespace

std::vector<SectionDigest> case_digests(const YAML::Node& root) {
  std::vector<SectionDigest> out;
  if (!root.IsMap()) return out;
  for (const auto& entry : root) {
    const std::string key = entry.first.as<std::string>();
    if (key == "study") continue;
    YAML::Node section = YAML::Clone(entry.second);
    if (section.IsMap() && key == "output") {
      section.remove("directory");
      section.remove("checkpoint_every");
    }
    if (section.IsMap() && key == "time") section.remove("end");
    YAML::Emitter emitter;
    emitter << section;
    out.push_back({key, checksum64(std::string_view(emitter.c_str(), emitter.size()))});
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  return out;
}

SectionDigest mesh_digest(const mesh::Mesh& m) {
  std::uint64_t h = checksum64(std::as_bytes(std::span(m.nodes.data(), m.nodes.size())));
  h = checksum64(std::as_bytes(std::span(m.cells.connectivity)), h);
  h = checksum64(std::as_bytes(std::span(&m.cells.type, 1)), h);
  for (const auto& g : m.group_names()) h = checksum64(std::as_bytes(std::span(g.data(), g.size())), h);
  return {"mesh " + m.name, h};
}

fs::path checkpoint_path(const fs::path& dir, long step) { return dir / fmt::format("checkpoint_{:06}.ckpt", step); }

bool is_checkpoint_name(std::string_view name) {
  if (name.ends_with(".tmp")) name.remove_suffix(4);
  return checkpoint_step(name).has_value();
}

std::uint64_t write_checkpoint(const fs::path& dir, const CheckpointHeader& header, std::string_view payload) {
  ArchiveWriter head;
  put_header(head, header);
  const std::string& h = head.bytes();
  std::uint64_t sum = checksum64(std::as_bytes(std::span(h.data(), h.size())));
  sum = checksum64(std::as_bytes(std::span(payload.data(), payload.size())), sum);
  ArchiveWriter prefix;
  const std::uint32_t format = kCheckpointFormat;
  prefix.put(format);
  prefix.put(static_cast<std::uint64_t>(h.size()));
  prefix.put(static_cast<std::uint64_t>(payload.size()));
  prefix.put(sum);

  const fs::path file = checkpoint_path(dir, header.step);
  try {
    write_file_atomically_synced(file, {kMagic, prefix.bytes(), h, payload});
  } catch (const Error& e) {
    throw Error(fmt::format("{}; the previous checkpoints are kept", e.what()));
  }
  const std::uint64_t bytes = kMagic.size() + prefix.bytes().size() + h.size() + payload.size();
  if (!process_writes_files()) return bytes;  // a distributed run's other ranks: rank 0 writes it
  std::error_code ec;
  // The new one is complete: keep it and the newest other one; drop the .tmp a killed
  // write left.
  std::vector<fs::path> stale;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.ends_with(".tmp") && is_checkpoint_name(name)) stale.push_back(it->path());
  }
  for (const fs::path& p : stale) fs::remove(p, ec);
  auto all = checkpoints_in(dir);
  std::size_t keep = 2;
  for (auto it = all.rbegin(); it != all.rend(); ++it) {
    if (keep > 0) {
      --keep;
      continue;
    }
    fs::remove(it->second, ec);
  }
  return bytes;
}

namespace {

struct Prefix {
  std::uint64_t header_bytes = 0, payload_bytes = 0, sum = 0;
};

/// The signature, the format and the sizes, from the first min(size, kPrefix) bytes of a
/// file of `size` bytes.
Prefix check_prefix(std::string_view first, std::uintmax_t size, const std::string& name) {
  if (first.size() < kMagic.size() || first.substr(0, kMagic.size()) != kMagic)
    throw Error(fmt::format("{}: not a shellflow checkpoint (no 'shellflow checkpoint' signature)", name));
  if (first.size() < kPrefix)
    throw Error(fmt::format("{}: truncated ({} bytes, not even the header); restart from an earlier checkpoint", name,
                            first.size()));
  ArchiveReader prefix(first.substr(kMagic.size(), kPrefix - kMagic.size()), name);
  const auto format = prefix.get<std::uint32_t>();
  if (format != kCheckpointFormat)
    throw Error(
        fmt::format("{}: checkpoint format {}, this shellflow reads format {}; continue it with the "
                    "shellflow that wrote it",
                    name, format, kCheckpointFormat));
  Prefix p;
  p.header_bytes = prefix.get<std::uint64_t>();
  p.payload_bytes = prefix.get<std::uint64_t>();
  p.sum = prefix.get<std::uint64_t>();
  const std::uintmax_t body = size - kPrefix;
  if (p.header_bytes > body || p.payload_bytes > body - p.header_bytes)
    throw Error(fmt::format("{}: truncated ({} bytes of {}); restart from an earlier checkpoint", name, size,
                            kPrefix + p.header_bytes + p.payload_bytes));
  if (p.header_bytes + p.payload_bytes != body)
    throw Error(fmt::format("{}: {} bytes after the end of the checkpoint; the file is damaged", name,
                            body - p.header_bytes - p.payload_bytes));
  return p;
}

/// The checksum, the header and its sense, from the bytes after the prefix.
Checkpoint parse_rest(std::string_view rest, const Prefix& p, const fs::path& file) {
  const std::string name = printable(file.string());
  const std::string_view head = rest.substr(0, p.header_bytes), tail = rest.substr(p.header_bytes);
  if (checksum64(std::as_bytes(std::span(tail.data(), tail.size())),
                 checksum64(std::as_bytes(std::span(head.data(), head.size())))) != p.sum)
    throw Error(fmt::format("{}: checksum mismatch, the file is damaged; restart from an earlier checkpoint", name));
  Checkpoint c;
  c.file = file;
  ArchiveReader header(head, name);
  c.header = get_header(header);
  // The checksum is no signature (anyone can compute one): the header's sense is checked too.
  const CheckpointHeader& h = c.header;
  if (h.step < 0 || double(h.step) > kMaxSteps || !std::isfinite(h.time) || h.time < 0.0)
    throw Error(fmt::format("{}: damaged (step {}, t = {} s; a checkpoint is at a step in [0, {:.0e}] and a time >= 0)",
                            name, h.step, h.time, kMaxSteps));
  if (const auto named = checkpoint_step(file.filename().string()); named && *named != h.step)
    throw Error(
        fmt::format("{}: holds step {}, its name says step {}; the file was renamed or damaged", name, h.step, *named));
  c.payload = std::string(tail);
  return c;
}

}  // namespace

Checkpoint parse_checkpoint(std::string_view bytes, const fs::path& file) {
  const Prefix p =
      check_prefix(bytes.substr(0, std::min(bytes.size(), kPrefix)), bytes.size(), printable(file.string()));
  return parse_rest(bytes.substr(kPrefix), p, file);
}

Checkpoint read_checkpoint(const fs::path& file) {
  const std::string name = printable(file.string());
  std::error_code ec;
  const auto status = fs::status(file, ec);
  if (!fs::exists(status))
    throw Error(
        fmt::format("{}: no such checkpoint; give an output directory or one of its "
                    "checkpoint_NNNNNN.ckpt files",
                    name));
  if (!fs::is_regular_file(status)) throw Error(fmt::format("{}: not a checkpoint file", name));
  // The signature and the sizes first: a large file named like a checkpoint is refused
  // before anything is read whole.
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec) throw Error(fmt::format("{}: cannot read the checkpoint ({})", name, ec.message()));
  std::ifstream in(file, std::ios::binary);
  std::string bytes(std::size_t(std::min<std::uintmax_t>(size, kPrefix)), '\0');
  in.read(bytes.data(), std::streamsize(bytes.size()));
  if (!in) throw Error(fmt::format("{}: cannot read the checkpoint", name));
  const Prefix p = check_prefix(bytes, size, name);
  bytes.resize(std::size_t(size));
  in.read(bytes.data() + kPrefix, std::streamsize(size - kPrefix));
  if (!in) throw Error(fmt::format("{}: cannot read the checkpoint", name));
  return parse_rest(std::string_view(bytes).substr(kPrefix), p, file);
}

fs::path find_checkpoint(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_directory(path, ec)) return path;  // read_checkpoint says what is wrong with it
  const auto all = checkpoints_in(path);
  if (all.empty())
    throw Error(
        fmt::format("{}: no checkpoint_NNNNNN.ckpt in this directory; a run writes them with "
                    "output.checkpoint_every, --stop-after, --stop-at-wall or on Ctrl-C",
                    path.string()));
  return all.rbegin()->second;
}

std::uint64_t executable_build_id() {
  static const std::uint64_t id = [] {
    std::ifstream in("/proc/self/exe", std::ios::binary);
    if (!in) return std::uint64_t{0};
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return checksum64(std::as_bytes(std::span(bytes.data(), bytes.size())));
  }();
  return id;
}

std::string checkpoint_mismatch(const Checkpoint& c, const CheckpointHeader& now) {
  const std::string name = c.file.string();
  const CheckpointHeader& then = c.header;
  if (then.program_version != now.program_version)
    return fmt::format(
        "{}: written by shellflow {}, this is shellflow {}; continue it with the shellflow that "
        "wrote it",
        name, printable(then.program_version), now.program_version);
  if (then.case_name != now.case_name)
    return fmt::format("{}: a checkpoint of case '{}', not of '{}'", name, printable(then.case_name), now.case_name);
  std::vector<std::string> changed;
  for (const auto& d : then.digests) {
    const auto it =
        std::find_if(now.digests.begin(), now.digests.end(), [&](const auto& e) { return e.name == d.name; });
    if (it == now.digests.end())
      changed.push_back(printable(d.name) + " (removed)");
    else if (it->digest != d.digest)
      changed.push_back(printable(d.name));
  }
  for (const auto& d : now.digests)
    if (std::none_of(then.digests.begin(), then.digests.end(), [&](const auto& e) { return e.name == d.name; }))
      changed.push_back(d.name + " (added)");
  if (!changed.empty()) {
    std::string list;
    for (const auto& s : changed) list += (list.empty() ? "" : ", ") + s;
    return fmt::format(
        "{}: the case changed since the checkpoint was written (sections: {}); restore them, or "
        "start a new run without --restart (time.end, output.checkpoint_every and study may "
        "change)",
        name, list);
  }
  return {};
}

}  // namespace shellflow::io
