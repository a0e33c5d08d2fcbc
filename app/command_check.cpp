// `shellflow check`: validate a case file without running it.
#include <fmt/format.h>

#include "commands.h"
#include "output_dir.h"
#include "shellflow/io/case_meshes.h"

namespace shellflow::app {

int check_command(const CommonOptions& options) {
  const io::Case c = read_case(options);
  io::check_case_groups(c);  // reads the groups from the .geo/.msh files, no meshing
  std::size_t meshes = 0;
  for (auto key : io::kMeshKeys) meshes += c.meshes.find(key) != nullptr;
  fmt::print("{}: OK (case '{}': {} mesh(es), {} physical-group reference(s), {} probe(s))\n",
             options.case_file.string(), c.name, meshes, c.group_references.size(),
             c.probes.size());
  return 0;
}

}  // namespace shellflow::app
