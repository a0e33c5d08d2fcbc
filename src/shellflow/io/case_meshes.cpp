#include "shellflow/io/case_meshes.h"

#include <fmt/format.h>
#include <gmsh.h>
#include <spdlog/spdlog.h>

#include <fstream>
#include <iterator>
#include <map>

#include "shellflow/core/archive.h"
#include "shellflow/core/error.h"
#include "shellflow/core/output_file.h"
#include "shellflow/core/version.h"
#include "shellflow/mesh/gmsh_input_check.h"
#include "shellflow/mesh/gmsh_io.h"

namespace shellflow::io {
namespace {

int expected_dim(std::string_view key) { return key == "shell" ? 2 : 3; }

// ---- the mesh cache (docs/output.md) ----------------------------------------------------------
//
// `<dir>/<key>.msh.cache`, beside the `<key>.msh` a run saves:
//   "shellflow mesh cache\n"  magic
//   u32 format, u64 input digest, u64 checksum of <key>.msh's bytes,
//   u64 payload bytes, u64 checksum of the payload
//   payload: the Mesh as extracted from Gmsh (core/archive.h: doubles as their bits)
// The input digest covers the bytes of the .geo and of every file Gmsh reads with it
// (Include, Merge, ShapeFromFile, FILE.opt), the meshing options, the Gmsh API version and
// shellflow's version. A cache is used only when that digest matches, the `.msh` beside it is
// the one written with it, and the file is complete (checksum); anything else is a miss.

namespace fs = std::filesystem;
constexpr std::string_view kCacheMagic = "shellflow mesh cache\n";
constexpr std::uint32_t kCacheFormat = 1;

std::optional<std::string> read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) return std::nullopt;
  return bytes;
}

std::uint64_t checksum_of(std::string_view bytes) { return checksum64(std::as_bytes(std::span(bytes))); }

std::uint64_t input_digest(const MeshSpec& spec, const mesh::MeshingOptions& options) {
  ArchiveWriter key;
  key.put(std::string_view(shellflow::version));
  key.put(std::string_view(GMSH_API_VERSION));
  key.put(spec.key);
  key.put(options.order);
  key.put(options.size_factor);
  key.put(options.dim);
  // Checks the script as generate_mesh would (the same InputError for a bad one).
  for (const fs::path& file : mesh::gmsh_input_files(spec.file)) {
    const auto bytes = read_bytes(file);
    if (!bytes) throw_input_error("{}: cannot read the file", file.string());
    key.put(checksum_of(*bytes));
  }
  return checksum_of(key.bytes());
}

void put_block(ArchiveWriter& out, const mesh::ElementBlock& b) {
  out.put(static_cast<int>(b.type));
  out.put(b.connectivity);
}

mesh::ElementBlock get_block(ArchiveReader& in, Index num_nodes) {
  mesh::ElementBlock b;
  const int type = in.get<int>();
  b.connectivity = in.get_vector<Index>();
  b.type = static_cast<mesh::ElementType>(mesh::element_info(type).type);  // throws for an unknown type
  if (b.connectivity.size() % static_cast<std::size_t>(b.nodes_per_element()) != 0)
    throw Error(in.what() + ": damaged connectivity");
  for (const Index i : b.connectivity)
    if (i < 0 || i >= num_nodes) throw Error(in.what() + ": node index out of range");
  return b;
}

std::string mesh_payload(const mesh::Mesh& m) {
  ArchiveWriter out;
  out.put(m.name);
  out.put(m.source);
  out.put(m.nodes);
  out.put(m.node_tags);
  put_block(out, m.cells);
  out.put(static_cast<std::uint64_t>(m.groups.size()));
  for (const auto& g : m.groups) {
    out.put(g.name);
    out.put(g.dim);
    out.put(g.tag);
    put_block(out, g.elements);
    out.put(g.nodes);
    out.put(g.cells);
  }
  return out.take();
}

mesh::Mesh mesh_from_payload(std::string_view payload, const std::string& what) {
  ArchiveReader in(payload, what);
  mesh::Mesh m;
  m.name = in.get_string();
  m.source = in.get_string();
  m.nodes = in.get_vec3s();
  m.node_tags = in.get_vector<std::size_t>();
  const Index n = m.num_nodes();
  if (m.node_tags.size() != m.nodes.size()) throw Error(what + ": damaged node tags");
  m.cells = get_block(in, n);
  const auto groups = in.get<std::uint64_t>();
  if (groups > in.remaining()) throw Error(what + ": damaged group count");
  for (std::uint64_t k = 0; k < groups; ++k) {
    mesh::PhysicalGroup g;
    g.name = in.get_string();
    g.dim = in.get<int>();
    g.tag = in.get<int>();
    g.elements = get_block(in, n);
    g.nodes = in.get_vector<Index>();
    g.cells = in.get_vector<Index>();
    for (const Index i : g.nodes)
      if (i < 0 || i >= n) throw Error(what + ": damaged group nodes");
    for (const Index i : g.cells)
      if (i < 0 || i >= m.num_cells()) throw Error(what + ": damaged group cells");
    m.groups.push_back(std::move(g));
  }
  in.expect_end();
  return m;
}

/// The cached mesh, or nullopt with the reason in `why`.
std::optional<mesh::Mesh> read_cache(const fs::path& cache, const fs::path& msh, std::uint64_t input,
                                     std::string& why) {
  std::error_code ec;
  if (!fs::exists(cache, ec)) {
    why = "no cache";
    return std::nullopt;
  }
  try {
    const auto bytes = read_bytes(cache);
    if (!bytes) throw Error("unreadable");
    if (bytes->size() < kCacheMagic.size() + 4 + 4 * 8 ||
        std::string_view(*bytes).substr(0, kCacheMagic.size()) != kCacheMagic)
      throw Error("not a mesh cache");
    ArchiveReader in(std::string_view(*bytes).substr(kCacheMagic.size()), cache.string());
    if (in.get<std::uint32_t>() != kCacheFormat) throw Error("another format");
    if (in.get<std::uint64_t>() != input) {
      why = "stale: the .geo, a file it reads, the meshing options or the Gmsh version changed";
      return std::nullopt;
    }
    const auto msh_sum = in.get<std::uint64_t>();
    const auto msh_bytes = read_bytes(msh);
    if (!msh_bytes || checksum_of(*msh_bytes) != msh_sum) {
      why = fmt::format("{} is missing or not the one written with the cache", msh.filename().string());
      return std::nullopt;
    }
    const auto size = in.get<std::uint64_t>();
    const auto sum = in.get<std::uint64_t>();
    if (size != in.remaining()) throw Error("truncated");
    const std::string_view payload = std::string_view(*bytes).substr(bytes->size() - size);
    if (checksum_of(payload) != sum) throw Error("checksum mismatch");
    return mesh_from_payload(payload, cache.string());
  } catch (const std::exception& e) {
    why = fmt::format("damaged ({})", e.what());
    return std::nullopt;
  }
}

/// Writes the cache (tmp + rename). A failure only costs the next run a meshing: a warning.
void write_cache(const fs::path& cache, const fs::path& msh, std::uint64_t input, const mesh::Mesh& m) {
  const auto msh_bytes = read_bytes(msh);
  try {
    if (msh_bytes) {
      const std::string payload = mesh_payload(m);
      ArchiveWriter head;
      head.put(kCacheFormat);
      head.put(input);
      head.put(checksum_of(*msh_bytes));
      head.put(static_cast<std::uint64_t>(payload.size()));
      head.put(checksum_of(payload));
      write_file_atomically(cache, std::string(kCacheMagic) + head.bytes() + payload);
      return;
    }
  } catch (const Error& e) {
    spdlog::warn("{}; the next run meshes again", e.what());
    return;
  }
  spdlog::warn("{}: cannot write the mesh cache; the next run meshes again", cache.string());
}

mesh::MeshingOptions meshing_options(const MeshSpec& spec) {
  mesh::MeshingOptions options;
  options.order = spec.order;
  options.size_factor = spec.size_factor;
  options.dim = expected_dim(spec.key);
  options.size_factor_key = "meshes." + spec.key + ".size_factor";
  return options;
}

mesh::Mesh load_one(const MeshSpec& spec, const std::optional<fs::path>& msh_dir,
                    const std::optional<fs::path>& cache_dir) {
  mesh::Mesh m;
  if (spec.format == MeshFormat::geo) {
    mesh::MeshingOptions options = meshing_options(spec);
    if (msh_dir) options.msh_output = *msh_dir / (spec.key + ".msh");
    const auto dir = msh_dir ? msh_dir : cache_dir;
    std::optional<std::uint64_t> input;
    std::optional<mesh::Mesh> cached;
    std::string why;
    if (dir) {
      input = input_digest(spec, options);
      cached = read_cache(*dir / (spec.key + ".msh.cache"), *dir / (spec.key + ".msh"), *input, why);
    }
    if (cached) {
      m = std::move(*cached);
      m.name = spec.key;  // as generate_mesh names them
      m.source = spec.file.string();
      spdlog::info("{} mesh: from the cache {} ({} unchanged)", spec.key, (*dir / (spec.key + ".msh.cache")).string(),
                   spec.as_written);
    } else {
      if (dir) spdlog::info("{} mesh: meshing {} ({})", spec.key, spec.as_written, why);
      m = mesh::generate_mesh(spec.file, options, spec.key);
      if (msh_dir) write_cache(*msh_dir / (spec.key + ".msh.cache"), *options.msh_output, *input, m);
    }
  } else {
    m = mesh::read_msh(spec.file, spec.key);
    // The run's copy `<key>.msh` (not when the input is that file: a mesh input inside the
    // output folder stays as it is).
    const fs::path copy = msh_dir ? *msh_dir / (spec.key + ".msh") : fs::path();
    std::error_code ec;
    if (msh_dir && !fs::equivalent(spec.file, copy, ec)) {
      const auto bytes = read_bytes(spec.file);
      if (!bytes)
        throw Error(fmt::format("{}: cannot read it again to copy it to {}", spec.file.string(), copy.string()));
      write_file_atomically(copy, *bytes);
    }
  }
  const auto& where = spec.where;
  if (m.dim() != expected_dim(spec.key)) {
    throw_at(where, fmt::format("{} holds a {}-D mesh of {}s; the {} mesh must be made of {}", spec.as_written, m.dim(),
                                mesh::element_info(m.cells.type).name, spec.key,
                                expected_dim(spec.key) == 3 ? "tetrahedra" : "triangles"));
  }
  if (spec.key == "space" && m.cells.type != mesh::ElementType::tet20) {
    throw_at(where, fmt::format("the space mesh must be made of 20-node (cubic) tetrahedra, {} "
                                "holds {}s; set 'order: 3'",
                                spec.as_written, mesh::element_info(m.cells.type).name));
  }
  if (spec.key == "fluid" && m.cells.type != mesh::ElementType::tet4) {
    throw_at(where, fmt::format("the fluid mesh must be made of 4-node tetrahedra, {} holds {}s; "
                                "set 'order: 1'",
                                spec.as_written, mesh::element_info(m.cells.type).name));
  }
  const auto q = mesh::summarize_quality(m);
  if (q.inverted > 0) {
    throw_at(where, fmt::format("{} has {} inverted element(s) (worst: element {}, quality "
                                "{:.3g}); fix the geometry's orientation or the mesh",
                                spec.as_written, q.inverted, q.worst_cell, q.min));
  }
  return m;
}

}  // namespace

const mesh::Mesh* CaseMeshes::find(std::string_view key) const {
  const auto& slot = key == "fluid" ? fluid : key == "space" ? space : shell;
  if (key != "fluid" && key != "space" && key != "shell") return nullptr;
  return slot ? &*slot : nullptr;
}

std::vector<const mesh::Mesh*> CaseMeshes::all() const {
  std::vector<const mesh::Mesh*> result;
  for (auto key : kMeshKeys)
    if (const auto* m = find(key)) result.push_back(m);
  return result;
}

CaseMeshes load_case_meshes(const Case& c, const std::optional<std::filesystem::path>& msh_dir,
                            const std::optional<std::filesystem::path>& cache_dir) {
  CaseMeshes meshes;
  if (c.meshes.fluid) meshes.fluid = load_one(*c.meshes.fluid, msh_dir, cache_dir);
  if (c.meshes.space) meshes.space = load_one(*c.meshes.space, msh_dir, cache_dir);
  if (c.meshes.shell) meshes.shell = load_one(*c.meshes.shell, msh_dir, cache_dir);
  check_physical_groups(c, [&](std::string_view key) {
    const auto* m = meshes.find(key);
    return m ? m->group_names() : std::vector<std::string>{};
  });
  return meshes;
}

void check_case_groups(const Case& c) {
  // A size factor that would make a mesh beyond the machine: refused here too, not by the run.
  for (const MeshSpec* spec : {c.meshes.fluid ? &*c.meshes.fluid : nullptr, c.meshes.space ? &*c.meshes.space : nullptr,
                               c.meshes.shell ? &*c.meshes.shell : nullptr})
    if (spec && spec->format == MeshFormat::geo) {
      mesh::check_mesh_size_of(spec->file, meshing_options(*spec));
    }
  check_physical_groups(c, [&](std::string_view key) {
    const auto* spec = c.meshes.find(key);
    return spec ? mesh::physical_group_names(spec->file) : std::vector<std::string>{};
  });
}

MeshReport report_mesh(const mesh::Mesh& m) {
  const auto& info = mesh::element_info(m.cells.type);
  return {m.name,
          m.source,
          m.num_nodes(),
          m.num_cells(),
          info.short_name,
          static_cast<int>(m.cells.type),
          mesh::summarize_quality(m)};
}

std::string reports_to_json(const std::vector<MeshReport>& reports) {
  auto escape = [](const std::string& s) {
    std::string out;
    for (char ch : s) {
      if (ch == '"' || ch == '\\') out += '\\';
      out += ch;
    }
    return out;
  };
  std::string json = "{";
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const auto& r = reports[i];
    json += fmt::format(
        "{}\"{}\": {{\"nodes\": {}, \"elements\": {}, \"element_type\": \"{}\", \"gmsh_type\": {}, "
        "\"min_quality\": {:.6g}, \"mean_quality\": {:.6g}, \"inverted\": {}, \"source\": \"{}\"}}",
        i ? ", " : "", r.key, r.nodes, r.elements, r.element_type, r.gmsh_type, r.quality.min, r.quality.mean,
        r.quality.inverted, escape(r.source));
  }
  return json + "}";
}

}  // namespace shellflow::io
