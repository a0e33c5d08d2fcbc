// shellflow: thin elastic shells in compressible gas flow.
//
//   shellflow mesh  cases/panel_flutter/clamped_clamped.yaml [-o OUTDIR] [--json]
//   shellflow check cases/panel_flutter/clamped_clamped.yaml
//   shellflow run   cases/panel_flutter/clamped_clamped.yaml [-o OUTDIR]
//
// Every error the user can fix is printed as one line `shellflow: error: ...` and the
// exit code is 1 (2 for a bad command line).
#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <exception>

#include "commands.h"
#include "shellflow/core/error.h"
#include "shellflow/core/version.h"

int main(int argc, char** argv) {
  using namespace shellflow;
  // Log to stderr so that stdout carries only results (tables, JSON).
  auto logger = spdlog::stderr_color_mt("shellflow");
  spdlog::set_default_logger(logger);
  spdlog::set_pattern("[%H:%M:%S] %^%l%$: %v");

  CLI::App cli{"shellflow: geometrically nonlinear shells in compressible gas flow "
               "(positional shell FEM, ALE Taylor-Galerkin flow, space-mesh fluid mesh motion)",
               "shellflow"};
  cli.set_version_flag("--version", std::string("shellflow ") + shellflow::version);
  cli.require_subcommand(1);
  cli.fallthrough();  // -v/-q also after the subcommand
  bool verbose = false, quiet = false;
  cli.add_flag("-v,--verbose", verbose, "Print debug messages (and Gmsh's progress)");
  cli.add_flag("-q,--quiet", quiet, "Print warnings and errors only");

  app::CommonOptions options;
  bool json = false;
  auto add_case = [&](CLI::App* sub) {
    sub->add_option("case", options.case_file, "Case file (YAML); see docs/case-format.md")
        ->required()
        ->check(CLI::ExistingFile);
  };
  auto add_output = [&](CLI::App* sub) {
    sub->add_option("-o,--output", options.output_dir,
                    "Output directory (default: the case's output.directory, else out/<name>)");
    sub->add_flag("!--no-plot", options.plot, "Do not make the PNG plots at the end");
  };

  auto* run = cli.add_subcommand(
      "run", "Run a case: mesh it, integrate in time (shell, flow, mesh motion, or all coupled "
             "with a 'coupling' section: panel flutter), write .vtu/.pvd fields, probes.csv and "
             "plots (coupled runs: coupling.csv, mesh_quality.csv, flutter.png)");
  add_case(run);
  add_output(run);
  auto* mesh = cli.add_subcommand(
      "mesh", "Mesh a case's geometries (fluid, space and shell meshes): write <mesh>.msh and "
              "<mesh>.vtu, print sizes and quality, plot the meshes");
  add_case(mesh);
  add_output(mesh);
  mesh->add_flag("--json", json,
                 "Print one JSON object: per mesh nodes, elements, element_type, min_quality");
  auto* check = cli.add_subcommand(
      "check", "Validate a case file (keys, types, ranges, files, physical groups) without "
               "running it");
  add_case(check);

  CLI11_PARSE(cli, argc, argv);
  spdlog::set_level(verbose ? spdlog::level::debug
                    : quiet ? spdlog::level::warn
                            : spdlog::level::info);
  try {
    if (*run) return app::run_command(options);
    if (*mesh) return app::mesh_command(options, json);
    if (*check) return app::check_command(options);
  } catch (const Error& e) {
    std::fprintf(stderr, "shellflow: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "shellflow: internal error: %s\n", e.what());
    return 3;
  }
  return 0;
}
