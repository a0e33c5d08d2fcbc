// `shellflow mesh`: mesh a case's geometries and report sizes and quality.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "shellflow/core/error.h"
#include "shellflow/core/output_file.h"
#include "shellflow/coupling/wall_resolution.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/io/mesh_output.h"
#include "shellflow/setup/shell_setup.h"

namespace shellflow::app {
namespace {

/// A coupled case with a flow: the cells of its wet wall per λ_x/M of the shell's first two
/// out-of-plane modes (docs/fluid.md, "Cells per wavelength").
std::optional<coupling::WallResolution> wall_resolution(const io::Case& c, const io::CaseMeshes& meshes) {
  if (!c.coupling || c.coupling->fluid_group.empty() || !c.shell || !c.fluid || !c.fluid->analysis || !meshes.fluid ||
      !meshes.shell)
    return std::nullopt;
  // The meshes are the command's product: a shell that cannot be analysed (too few supports,
  // a modal iteration that fails) only costs the report, with the reason.
  try {
    const shell::ShellModel model = setup::build_shell_model(*c.shell, *meshes.shell);
    return coupling::wall_resolution(model, *meshes.fluid, c.coupling->fluid_group, c.fluid->free_stream.direction,
                                     c.fluid->free_stream.mach);
  } catch (const Error& e) {
    spdlog::warn("no cells-per-wavelength report of the wet wall: {}", e.what());
    return std::nullopt;
  }
}

void print_resolution(const coupling::WallResolution& r, const std::string& group) {
  fmt::print(
      "\nwet wall '{}': cells {:.4g} m long in the stream; cells per lambda_x/M at Mach {:.4g} (8 or more keeps the "
      "wall pressure within 0.5-3 %)\n",
      group, r.cell_size, r.mach);
  fmt::print("{:>6} {:>10} {:>12} {:>14} {:>8}\n", "mode", "f [Hz]", "lambda_x [m]", "lambda_x/M [m]", "cells");
  for (const auto& m : r.modes)
    fmt::print("{:>6} {:>10.4g} {:>12.4g} {:>14.4g} {:>8.3g}\n", m.mode, m.frequency_hz, m.wavelength,
               m.front_wavelength, m.cells);
}

}  // namespace

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
  const auto resolution = wall_resolution(c, meshes);
  std::string report_json = io::reports_to_json(reports);
  if (resolution) report_json.insert(report_json.size() - 1, ", \"wet_wall\": " + coupling::to_json(*resolution));
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
    if (resolution) print_resolution(*resolution, c.coupling->fluid_group);
  }
  std::fflush(stdout);
  spdlog::info("wrote {}: <mesh>.msh, <mesh>.vtu, meshes.json", outdir.string());
  // With --json, stdout carries the JSON object only: the plot script's messages go to stderr.
  if (options.plot) make_plot("plot_mesh.py", {outdir.string()}, json);
  return 0;
}

Command add_mesh_command(CLI::App& cli, CommonOptions& common) {
  auto json = std::make_shared<bool>(false);
  auto* sub = cli.add_subcommand("mesh",
                                 "Mesh a case's geometries (fluid, space and shell meshes): write <mesh>.msh and "
                                 "<mesh>.vtu, print sizes and quality (and, for a coupled case with a flow, the wet "
                                 "wall's cells per lambda_x/M, docs/fluid.md), plot the meshes");
  add_case_options(sub, common);
  add_output_options(sub, common);
  sub->add_flag("--json", *json,
                "Print one JSON object: per mesh nodes, elements, element_type, min_quality; for a coupled case "
                "with a flow, \"wet_wall\": the wet wall's cells per lambda_x/M of the shell's first two modes");
  return {sub, [&common, json] { return mesh_command(common, *json); }};
}

}  // namespace shellflow::app
