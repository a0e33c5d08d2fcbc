// `shellflow check`: validate a case file without running it.
#include <fmt/format.h>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/mesh/gmsh_input_check.h"

namespace shellflow::app {

int check_command(const CommonOptions& options) {
  const io::Case c = read_case(options);
  // Every mesh file as `run` checks it before Gmsh opens it (a .geo runs nothing, a .msh is a
  // sound mesh), also those no physical group is looked up in.
  for (auto key : io::kMeshKeys)
    if (const io::MeshSpec* spec = c.meshes.find(key)) mesh::check_gmsh_input(spec->file);
  io::check_case_groups(c);                   // reads the groups from the .geo/.msh files, no meshing
  if (c.study) check_study_case(c, options);  // study.set as `study` applies it
  std::size_t meshes = 0;
  for (auto key : io::kMeshKeys) meshes += c.meshes.find(key) != nullptr;
  fmt::print("{}: OK (case '{}': {} mesh(es), {} physical-group reference(s), {} probe(s))\n",
             options.case_file.string(), c.name, meshes, c.group_references.size(), c.probes.size());
  return 0;
}

Command add_check_command(CLI::App& cli, CommonOptions& common) {
  auto* sub = cli.add_subcommand("check",
                                 "Validate a case file (keys, types, ranges, files, physical groups) without "
                                 "running it");
  add_case_options(sub, common);
  return {sub, [&common] { return check_command(common); }};
}

}  // namespace shellflow::app
