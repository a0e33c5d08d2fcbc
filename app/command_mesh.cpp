// `shellflow mesh`: mesh a case's geometries and report sizes and quality.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <unistd.h>

#include <cstdio>
#include <fstream>

#include "commands.h"
#include "output_dir.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/io/mesh_output.h"

namespace shellflow::app {

int mesh_command(const CommonOptions& options, bool json) {
  const io::Case c = io::read_case(options.case_file);
  const auto outdir = prepare_output_dir(c, options);
  spdlog::info("meshing {} into {}", options.case_file.string(), outdir.string());
  const io::CaseMeshes meshes = io::load_case_meshes(c, outdir);

  std::vector<io::MeshReport> reports;
  for (const mesh::Mesh* m : meshes.all()) {
    io::write_mesh_vtu(outdir / (m->name + ".vtu"), *m);
    reports.push_back(io::report_mesh(*m));
  }
  const std::string report_json = io::reports_to_json(reports);
  std::ofstream(outdir / "meshes.json") << report_json << '\n';

  if (json) {
    fmt::print("{}\n", report_json);
  } else {
    fmt::print("{:<6} {:>8} {:>9}  {:<6} {:>7} {:>7} {:>8}  {}\n", "mesh", "nodes", "elements",
               "type", "min q", "mean q", "inverted", "source");
    for (const auto& r : reports) {
      fmt::print("{:<6} {:>8} {:>9}  {:<6} {:>7.3f} {:>7.3f} {:>8}  {}\n", r.key, r.nodes,
                 r.elements, r.element_type, r.quality.min, r.quality.mean, r.quality.inverted,
                 r.source);
    }
  }
  std::fflush(stdout);
  spdlog::info("wrote {}: <mesh>.msh, <mesh>.vtu, meshes.json", outdir.string());
  if (options.plot) {
    if (json) {
      // stdout carries the JSON object only: the plot script's own messages go to stderr.
      const int saved_stdout = ::dup(STDOUT_FILENO);
      if (saved_stdout < 0 || ::dup2(STDERR_FILENO, STDOUT_FILENO) < 0) {
        spdlog::warn("plot skipped: cannot keep its messages off stdout (--json)");
        if (saved_stdout >= 0) ::close(saved_stdout);
        return 0;
      }
      make_plot("plot_mesh.py", {outdir.string()});
      std::fflush(stdout);
      ::dup2(saved_stdout, STDOUT_FILENO);
      ::close(saved_stdout);
    } else {
      make_plot("plot_mesh.py", {outdir.string()});
    }
  }
  return 0;
}

}  // namespace shellflow::app
