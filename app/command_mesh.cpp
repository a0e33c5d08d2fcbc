// `shellflow mesh`: mesh a case's geometries and report sizes and quality.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cstdio>

#include "commands.h"
#include "shellflow/core/output_file.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/io/mesh_output.h"

namespace shellflow::app {

int mesh_command(const CommonOptions& options, bool json) {
  const io::Case c = read_case(options);
  const auto folder = prepare_output_dir(c, options);  // locked while this command runs
  const std::filesystem::path& outdir = folder.path;
  spdlog::info("meshing {} into {}", options.case_file.string(), outdir.string());
  const io::CaseMeshes meshes = io::load_case_meshes(c, outdir);

  std::vector<io::MeshReport> reports;
  for (const mesh::Mesh* m : meshes.all()) {
    io::write_mesh_vtu(outdir / (m->name + ".vtu"), *m);
    reports.push_back(io::report_mesh(*m));
  }
  const std::string report_json = io::reports_to_json(reports);
  write_file_atomically(outdir / "meshes.json", report_json + '\n');

  if (json) {
    fmt::print("{}\n", report_json);
  } else {
    fmt::print("{:<6} {:>8} {:>9}  {:<6} {:>7} {:>7} {:>8}  {}\n", "mesh", "nodes", "elements", "type", "min q",
               "mean q", "inverted", "source");
    for (const auto& r : reports) {
      fmt::print("{:<6} {:>8} {:>9}  {:<6} {:>7.3f} {:>7.3f} {:>8}  {}\n", r.key, r.nodes, r.elements, r.element_type,
                 r.quality.min, r.quality.mean, r.quality.inverted, r.source);
    }
  }
  std::fflush(stdout);
  spdlog::info("wrote {}: <mesh>.msh, <mesh>.vtu, meshes.json", outdir.string());
  // With --json, stdout carries the JSON object only: the plot script's messages go to stderr.
  if (options.plot) make_plot("plot_mesh.py", {outdir.string()}, json);
  return 0;
}

}  // namespace shellflow::app
