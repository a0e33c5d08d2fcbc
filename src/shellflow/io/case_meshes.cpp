#include "shellflow/io/case_meshes.h"

#include <fmt/format.h>

#include <map>

#include "shellflow/core/error.h"
#include "shellflow/mesh/gmsh_io.h"

namespace shellflow::io {
namespace {

int expected_dim(std::string_view key) { return key == "shell" ? 2 : 3; }

mesh::Mesh load_one(const MeshSpec& spec, const std::optional<std::filesystem::path>& msh_dir) {
  mesh::Mesh m;
  if (spec.format == MeshFormat::geo) {
    mesh::MeshingOptions options;
    options.order = spec.order;
    options.size_factor = spec.size_factor;
    options.dim = expected_dim(spec.key);
    if (msh_dir) options.msh_output = *msh_dir / (spec.key + ".msh");
    m = mesh::generate_mesh(spec.file, options, spec.key);
  } else {
    m = mesh::read_msh(spec.file, spec.key);
    if (msh_dir) {
      std::filesystem::create_directories(*msh_dir);
      std::filesystem::copy_file(spec.file, *msh_dir / (spec.key + ".msh"),
                                 std::filesystem::copy_options::overwrite_existing);
    }
  }
  const auto& where = spec.where;
  if (m.dim() != expected_dim(spec.key)) {
    throw_at(where, fmt::format("{} holds a {}-D mesh of {}s; the {} mesh must be made of {}",
                      spec.as_written, m.dim(),
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

CaseMeshes load_case_meshes(const Case& c, const std::optional<std::filesystem::path>& msh_dir) {
  CaseMeshes meshes;
  if (c.meshes.fluid) meshes.fluid = load_one(*c.meshes.fluid, msh_dir);
  if (c.meshes.space) meshes.space = load_one(*c.meshes.space, msh_dir);
  if (c.meshes.shell) meshes.shell = load_one(*c.meshes.shell, msh_dir);
  check_physical_groups(c, [&](std::string_view key) {
    const auto* m = meshes.find(key);
    return m ? m->group_names() : std::vector<std::string>{};
  });
  return meshes;
}

void check_case_groups(const Case& c) {
  check_physical_groups(c, [&](std::string_view key) {
    const auto* spec = c.meshes.find(key);
    return spec ? mesh::physical_group_names(spec->file) : std::vector<std::string>{};
  });
}

MeshReport report_mesh(const mesh::Mesh& m) {
  const auto& info = mesh::element_info(m.cells.type);
  return {m.name, m.source, m.num_nodes(), m.num_cells(), info.short_name,
          static_cast<int>(m.cells.type), mesh::summarize_quality(m)};
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
        i ? ", " : "", r.key, r.nodes, r.elements, r.element_type, r.gmsh_type, r.quality.min,
        r.quality.mean, r.quality.inverted, escape(r.source));
  }
  return json + "}";
}

}  // namespace shellflow::io
