#include "shellflow/mesh/gmsh_io.h"

#include <gmsh.h>
#include <omp.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <numeric>
#include <thread>
#include <unordered_map>

#include "shellflow/core/error.h"
#include "shellflow/core/output_file.h"
#include "shellflow/mesh/gmsh_input_check.h"

namespace shellflow::mesh {
namespace {

/// Gmsh has one global state: initialise it once per use, serialise all uses, and turn
/// its errors (which it throws as various types) into InputError naming the file.
/// Gmsh also sets the process's OpenMP thread count to its General.NumThreads (1 by
/// default) when it meshes, which left every solver after the meshing on one thread: the
/// session puts the count back when it ends.
class GmshSession {
 public:
  explicit GmshSession(bool verbose) : lock_(mutex()), threads_(omp_get_max_threads()) {
    gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
    gmsh::option::setNumber("General.Terminal", verbose ? 1 : 0);
    gmsh::option::setNumber("General.Verbosity", verbose ? 5 : 2);
  }
  ~GmshSession() {
    gmsh::finalize();
    omp_set_num_threads(threads_);
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  std::lock_guard<std::mutex> lock_;
  int threads_;
};

std::string last_gmsh_error() {
  std::string message;
  try {
    gmsh::logger::getLastError(message);
  } catch (...) {
  }
  return message.empty() ? std::string("unknown Gmsh error") : message;
}

/// Runs `f`, converting any Gmsh failure into an InputError about `file`.
template <class F>
void with_gmsh(const std::filesystem::path& file, std::string_view action, F&& f) {
  try {
    f();
  } catch (const Error&) {
    throw;
  } catch (...) {
    throw_input_error("{}: Gmsh failed to {}: {}", file.string(), action, last_gmsh_error());
  }
}

/// The time limit on Gmsh reading a .geo: SHELLFLOW_GEO_TIMEOUT seconds, default 120, at most
/// kLongestGeoTimeout (11.6 days: no limit in practice; a larger value, say 1e18, would
/// overflow the watchdog's clock and fire at once).
constexpr double kLongestGeoTimeout = 1e6;

double geo_read_timeout() {
  const char* text = std::getenv("SHELLFLOW_GEO_TIMEOUT");
  if (!text || !*text) return 120.0;
  char* end = nullptr;
  const double seconds = std::strtod(text, &end);
  if (*end != '\0' || !std::isfinite(seconds) || !(seconds > 0.0))
    throw Error(fmt::format("SHELLFLOW_GEO_TIMEOUT='{}': expected the seconds Gmsh may take to read a .geo (> 0)",
                            printable(text)));
  return std::min(seconds, kLongestGeoTimeout);
}

/// A watchdog on Gmsh reading a .geo: a `Sleep 3600;` or a loop of 1e12 turns would hang
/// `check` and `run`, and Gmsh cannot be interrupted. When the limit expires the error line
/// is printed and the process ends with status 1 (what it wrote is complete: every output
/// is renamed into place whole).
class GeoReadLimit {
 public:
  explicit GeoReadLimit(const std::filesystem::path& file) : seconds_(geo_read_timeout()) {
    watchdog_ = std::thread([this, name = printable(file.string())] {
      std::unique_lock lock(mutex_);
      if (done_changed_.wait_for(lock, std::chrono::duration<double>(seconds_), [this] { return done_; })) return;
      std::fprintf(stderr,
                   "shellflow: error: %s: Gmsh did not finish reading it within %g s (a Sleep, or a loop too long?); "
                   "fix the .geo, or raise the limit with SHELLFLOW_GEO_TIMEOUT=seconds\n",
                   name.c_str(), seconds_);
      std::fflush(stderr);
      std::_Exit(1);
    });
  }
  ~GeoReadLimit() {
    {
      std::lock_guard lock(mutex_);
      done_ = true;
    }
    done_changed_.notify_all();
    watchdog_.join();
  }
  GeoReadLimit(const GeoReadLimit&) = delete;
  GeoReadLimit& operator=(const GeoReadLimit&) = delete;

 private:
  double seconds_;
  std::mutex mutex_;
  std::condition_variable done_changed_;
  bool done_ = false;
  std::thread watchdog_;
};

/// gmsh::open, under the time limit for a .geo.
void open_in_gmsh(const std::filesystem::path& file) {
  if (file.extension() == ".geo") {
    const GeoReadLimit limit(file);
    gmsh::open(file.string());
  } else {
    gmsh::open(file.string());
  }
}

void require_file(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) {
    throw_input_error(
        "{}: file not found (check the path; relative paths are relative to the "
        "case file)",
        file.string());
  }
}

/// Copies the model currently loaded in Gmsh into a Mesh: the cells of the highest
/// dimension (one element type), the nodes they use (renumbered 0..n-1 in Gmsh tag
/// order), and every named physical group.
Mesh extract_model(const std::filesystem::path& source, std::string mesh_name) {
  Mesh mesh;
  mesh.name = std::move(mesh_name);
  mesh.source = source.string();

  // Cells: elements of the highest dimension present.
  std::vector<int> types;
  int dim = -1;
  for (int d = 3; d >= 1 && dim < 0; --d) {
    std::vector<std::vector<std::size_t>> tags, nodes;
    gmsh::model::mesh::getElements(types, tags, nodes, d, -1);
    if (!types.empty()) dim = d;
  }
  if (dim < 0) throw_input_error("{}: the file holds no mesh elements", mesh.source);
  if (types.size() != 1) {
    throw_input_error(
        "{}: the {}-D mesh mixes {} element types; shellflow needs one type per "
        "mesh (no quads/prisms/pyramids: mesh without Recombine)",
        mesh.source, dim, types.size());
  }
  if (!is_supported_element_type(types[0])) {
    std::string name;
    int edim = 0, order = 0, nn = 0, npn = 0;
    std::vector<double> local;
    gmsh::model::mesh::getElementProperties(types[0], name, edim, order, nn, local, npn);
    throw_input_error(
        "{}: element type '{}' (Gmsh type {}) is not supported; use triangles or "
        "tetrahedra of order 1, 2 or 3 (no Recombine, complete elements)",
        mesh.source, name, types[0]);
  }
  mesh.cells.type = static_cast<ElementType>(types[0]);

  std::vector<std::size_t> cell_tags, cell_nodes;
  gmsh::model::mesh::getElementsByType(types[0], cell_tags, cell_nodes, -1);

  // Nodes used by the cells, in increasing tag order.
  std::vector<std::size_t> used(cell_nodes);
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::unordered_map<std::size_t, Index> index_of;
  index_of.reserve(used.size());
  for (std::size_t i = 0; i < used.size(); ++i) index_of.emplace(used[i], static_cast<Index>(i));

  std::vector<std::size_t> all_tags;
  std::vector<double> coords, param;
  gmsh::model::mesh::getNodes(all_tags, coords, param, -1, -1, false, false);
  mesh.nodes.assign(used.size(), Vec3::Zero());
  mesh.node_tags = used;
  for (std::size_t i = 0; i < all_tags.size(); ++i) {
    auto it = index_of.find(all_tags[i]);
    if (it != index_of.end()) {
      mesh.nodes[static_cast<std::size_t>(it->second)] = Vec3(coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]);
    }
  }

  mesh.cells.connectivity.resize(cell_nodes.size());
  std::transform(cell_nodes.begin(), cell_nodes.end(), mesh.cells.connectivity.begin(),
                 [&](std::size_t tag) { return index_of.at(tag); });
  std::unordered_map<std::size_t, Index> cell_index_of;
  cell_index_of.reserve(cell_tags.size());
  for (std::size_t i = 0; i < cell_tags.size(); ++i) cell_index_of.emplace(cell_tags[i], static_cast<Index>(i));

  // Physical groups.
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, -1);
  for (const auto& [gdim, gtag] : groups) {
    PhysicalGroup group;
    gmsh::model::getPhysicalName(gdim, gtag, group.name);
    if (group.name.empty()) group.name = std::to_string(gtag);
    group.dim = gdim;
    group.tag = gtag;
    if (gdim > dim) continue;  // e.g. a volume group of a surface-only mesh

    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(gdim, gtag, entities);
    bool type_set = false;
    for (int entity : entities) {
      std::vector<int> etypes;
      std::vector<std::vector<std::size_t>> etags, enodes;
      gmsh::model::mesh::getElements(etypes, etags, enodes, gdim, entity);
      for (std::size_t t = 0; t < etypes.size(); ++t) {
        if (gdim == 0) continue;
        if (!is_supported_element_type(etypes[t])) continue;
        if (type_set && static_cast<int>(group.elements.type) != etypes[t]) {
          throw_input_error("{}: physical group '{}' mixes element types", mesh.source, group.name);
        }
        group.elements.type = static_cast<ElementType>(etypes[t]);
        type_set = true;
        for (std::size_t tag : enodes[t]) {
          auto it = index_of.find(tag);
          if (it == index_of.end()) {
            throw_input_error(
                "{}: physical group '{}' has a node (tag {}) that no {}-D element "
                "uses; the group must lie on the mesh's boundary",
                mesh.source, group.name, tag, dim);
          }
          group.elements.connectivity.push_back(it->second);
        }
        if (gdim == dim) {
          for (std::size_t tag : etags[t]) group.cells.push_back(cell_index_of.at(tag));
        }
      }
    }
    std::vector<std::size_t> node_tags;
    std::vector<double> node_coords;
    gmsh::model::mesh::getNodesForPhysicalGroup(gdim, gtag, node_tags, node_coords);
    for (std::size_t tag : node_tags) {
      auto it = index_of.find(tag);
      if (it != index_of.end()) group.nodes.push_back(it->second);
    }
    std::sort(group.nodes.begin(), group.nodes.end());
    group.nodes.erase(std::unique(group.nodes.begin(), group.nodes.end()), group.nodes.end());
    std::sort(group.cells.begin(), group.cells.end());
    mesh.groups.push_back(std::move(group));
  }
  return mesh;
}

/// The elements of dimension `dim` (-1: the model's) of the mesh Gmsh holds.
std::size_t element_count(int dim) {
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> tags, nodes;
  gmsh::model::mesh::getElements(types, tags, nodes, dim >= 0 ? dim : gmsh::model::getDimension());
  std::size_t n = 0;
  for (const auto& t : tags) n += t.size();
  return n;
}

/// The elements of `geometry` meshed at `factor` (the script read again: a structured .geo
/// scales its cell counts by Mesh.MeshSizeFactor).
std::size_t probe_count(const std::filesystem::path& geometry, const MeshingOptions& options, double factor) {
  gmsh::clear();
  gmsh::option::setNumber("Mesh.MeshSizeFactor", factor);
  open_in_gmsh(geometry);
  gmsh::option::setNumber("Mesh.MeshSizeFactor", factor);
  gmsh::model::mesh::generate(options.dim > 0 ? options.dim : gmsh::model::getDimension());
  const std::size_t n = element_count(options.dim);
  gmsh::clear();
  return n;
}

/// Bytes a run needs per fluid element, with a margin: measured 0.46 kB per tetrahedron for
/// Gmsh's meshing and 0.75 kB for a coupled 3-D run (docs/mesh.md).
constexpr double kBytesPerElement = 2048.0;

double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && size > 0 ? double(pages) * double(size) : 0.0;
}

MeshSizeEstimate estimate_in_session(const std::filesystem::path& geometry, const MeshingOptions& options) {
  MeshSizeEstimate e;
  e.limit = physical_memory_bytes() / kBytesPerElement;
  if (!(options.size_factor < kSizeFactorProbedBelow)) return e;
  // Coarser than asked, at factors 1 and 0.5 (a 3-D mesh at 0.25 costs 8 times the one at
  // 0.5): the count at the factor asked extrapolated with the exponent the two give. Factors 2
  // and 1 were too coarse: on a small geometry the surface's share made the exponent 1.9 where
  // the mesh grows as 2.9, and the estimate fell short of the mesh by 3.6 times.
  std::size_t n1 = 0, n2 = 0;  // at factors 1 and 1/2
  try {
    n1 = probe_count(geometry, options, 1.0);
    n2 = probe_count(geometry, options, 0.5);
  } catch (const Error&) {
    throw;  // the time limit on a .geo, a script refused
  } catch (...) {
    gmsh::clear();
    return e;  // a geometry Gmsh cannot mesh coarse: the meshing at the factor asked says why, or works
  }
  if (n1 == 0 || n2 == 0) return e;
  // 0: a structured script that keeps its cell counts; at most the dimension (3 unless given).
  e.exponent = std::clamp(std::log2(double(n2) / double(n1)), 0.0, options.dim > 0 ? double(options.dim) : 3.0);
  e.at_factor_one = double(n1);
  e.elements = double(n2) * std::pow(2.0 * options.size_factor, -e.exponent);
  spdlog::info("{}: about {:.3g} elements at size factor {:.3g} ({} at 1, {} at 0.5; the machine holds about {:.2g})",
               geometry.filename().string(), e.elements, options.size_factor, n1, n2, e.limit);
  return e;
}

[[noreturn]] void throw_size_error(const std::filesystem::path& geometry, const MeshingOptions& options,
                                   const MeshSizeEstimate& e) {
  throw_input_error(
      "{}: {} {:.3g} would make about {:.2g} elements ({:.0f} at size factor 1, growing as factor^-{:.2g}); "
      "this machine's memory holds about {:.2g}; raise it to {:.2g} or more",
      geometry.string(), options.size_factor_key, options.size_factor, e.elements, e.at_factor_one, e.exponent, e.limit,
      std::pow(e.limit / e.at_factor_one, -1.0 / e.exponent));
}

void check_mesh_size_in_session(const std::filesystem::path& geometry, const MeshingOptions& options) {
  const MeshSizeEstimate e = estimate_in_session(geometry, options);
  if (e.elements > e.limit && e.limit > 0.0) throw_size_error(geometry, options, e);
}

}  // namespace

MeshSizeEstimate estimate_mesh_size(const std::filesystem::path& geometry, const MeshingOptions& options) {
  require_file(geometry);
  check_gmsh_input(geometry);
  GmshSession session(false);
  MeshSizeEstimate e;
  with_gmsh(geometry, "mesh the geometry", [&] { e = estimate_in_session(geometry, options); });
  return e;
}

void check_mesh_size_of(const std::filesystem::path& geometry, const MeshingOptions& options) {
  if (!(options.size_factor < kSizeFactorProbedBelow)) return;
  const MeshSizeEstimate e = estimate_mesh_size(geometry, options);
  if (e.elements > e.limit && e.limit > 0.0) throw_size_error(geometry, options, e);
}

Mesh generate_mesh(const std::filesystem::path& geometry, const MeshingOptions& options, std::string mesh_name) {
  require_file(geometry);
  if (options.order < 1 || options.order > 3) {
    throw_input_error("{}: element order {} is not supported; use 1, 2 or 3", geometry.string(), options.order);
  }
  if (!(options.size_factor > 0.0)) {
    throw_input_error("{}: mesh size factor must be > 0, got {}", geometry.string(), options.size_factor);
  }
  check_gmsh_input(geometry);  // no commands run from the script, no damaged mesh to Gmsh
  GmshSession session(options.verbose);
  Mesh mesh;
  with_gmsh(geometry, "mesh the geometry", [&] {
    check_mesh_size_in_session(geometry, options);  // refused before a mesh beyond the machine is begun
    // Set before the script runs, so that a structured .geo can scale its cell counts by it,
    // and again after, so that the case's value wins over one the script sets.
    gmsh::option::setNumber("Mesh.MeshSizeFactor", options.size_factor);
    open_in_gmsh(geometry);
    gmsh::option::setNumber("Mesh.MeshSizeFactor", options.size_factor);
    // Complete elements (tet20 has its 4 face nodes), high-order nodes on the geometry.
    gmsh::option::setNumber("Mesh.SecondOrderIncomplete", 0);
    gmsh::model::mesh::generate(options.dim > 0 ? options.dim : gmsh::model::getDimension());
    gmsh::model::mesh::setOrder(options.order);
    if (options.msh_output) {
      gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
      gmsh::option::setNumber("Mesh.Binary", 0);
      // Gmsh opens files by name: it writes a new file of ours, renamed into place (a link
      // named like the mesh is replaced, not written through).
      const std::filesystem::path& out = *options.msh_output;
      const auto tmp = private_temporary(out.parent_path().empty() ? "." : out.parent_path(), out.stem().string(),
                                         out.extension().string());
      try {
        gmsh::write(tmp.string());
      } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);  // the error on its way out is the one to report
        throw;
      }
      rename_into_place(tmp, out);
    }
    mesh = extract_model(geometry, std::move(mesh_name));
  });
  return mesh;
}

Mesh read_msh(const std::filesystem::path& msh, std::string mesh_name) {
  require_file(msh);
  check_msh_file(msh);  // read only as a mesh, and not a damaged one (Gmsh may crash)
  check_gmsh_option_files(msh);
  GmshSession session(false);
  Mesh mesh;
  with_gmsh(msh, "read the mesh", [&] {
    gmsh::open(msh.string());
    mesh = extract_model(msh, std::move(mesh_name));
  });
  return mesh;
}

std::vector<std::string> physical_group_names(const std::filesystem::path& file) {
  require_file(file);
  check_gmsh_input(file);  // `shellflow check` runs nothing a .geo asks for
  GmshSession session(false);
  std::vector<std::string> names;
  with_gmsh(file, "read the physical groups", [&] {
    open_in_gmsh(file);
    gmsh::vectorpair groups;
    gmsh::model::getPhysicalGroups(groups, -1);
    for (const auto& [dim, tag] : groups) {
      std::string name;
      gmsh::model::getPhysicalName(dim, tag, name);
      names.push_back(name.empty() ? std::to_string(tag) : name);
    }
  });
  return names;
}

}  // namespace shellflow::mesh
