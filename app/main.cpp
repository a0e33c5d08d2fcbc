// shellflow: thin elastic shells in compressible gas flow.
//
//   shellflow mesh  cases/panel_flutter/clamped_clamped.yaml [-o OUTDIR] [--json]
//   shellflow check cases/panel_flutter/clamped_clamped.yaml
//   shellflow run   cases/panel_flutter/clamped_clamped.yaml [-o OUTDIR] [--stop-after N]
//                   [--stop-at-wall S] [--restart OUTDIR[/checkpoint_NNNNNN.ckpt]]
//   shellflow flutter cases/panel_flutter/clamped_clamped_piston.yaml [--parameter mach] [--json]
//   shellflow partition cases/panel_flutter/clamped_clamped.yaml --parts N [-o OUTDIR]
//
// Every error the user can fix is printed as one line `shellflow: error: ...` and the
// exit code is 1 (2 for a bad command line); a run the physics stopped (a SolverError: Newton
// gave up, a negative density, an inverted element) exits with 4; a run stopped with a
// checkpoint (--stop-after, --stop-at-wall, SIGINT/SIGTERM) exits with 75.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <string>
#include <string_view>

#include "commands.h"
#include "shellflow/core/error.h"
#include "shellflow/core/output_file.h"
#include "shellflow/core/version.h"
#include "shellflow/dist/communicator.h"
#include "shellflow/fluid/residual.h"
#include "shellflow/run/run_control.h"

namespace {

/// The rank count and this process's rank as OpenMPI's or MPICH's launcher sets them (1 and 0
/// without a launcher).
long launcher_value(const char* openmpi, const char* mpich, long fallback) {
  for (const char* name : {openmpi, mpich})
    if (const char* value = std::getenv(name)) return std::atol(value);
  return fallback;
}
int launcher_ranks() { return int(launcher_value("OMPI_COMM_WORLD_SIZE", "PMI_SIZE", 1)); }
int launcher_rank() { return int(launcher_value("OMPI_COMM_WORLD_RANK", "PMI_RANK", 0)); }

}  // namespace

int main(int argc, char** argv) {
  using namespace shellflow;
  (void)run::process_start();  // --stop-at-wall counts from here
  // Log to stderr so that stdout carries only results (tables, JSON).
  auto logger = spdlog::stderr_color_mt("shellflow");
  spdlog::set_default_logger(logger);
  spdlog::set_pattern("[%H:%M:%S] %^%l%$: %v");

  CLI::App cli{
      "shellflow: geometrically nonlinear shells in compressible gas flow "
      "(positional shell FEM, ALE Taylor-Galerkin flow, space-mesh fluid mesh motion)",
      "shellflow"};
  cli.set_version_flag("--version", std::string("shellflow ") + shellflow::version);
  cli.require_subcommand(1);
  cli.footer(
      "Environment: OMP_NUM_THREADS (threads of a run; the results are the same bits on any count), "
      "SHELLFLOW_SPIN_US=microseconds (how long an idle thread spins before it sleeps; default 20), "
      "SHELLFLOW_SIMD=auto|sse2|avx2|avx2-fma|avx512 (instruction set of the flow's element "
      "pass; default auto: the best the CPU has; sse2 is the reference, avx2 gives its bits, "
      "avx2-fma and avx512 round differently), SHELLFLOW_GEO_TIMEOUT=seconds (the most Gmsh may take to read a "
      ".geo; default 120). An output folder is used by one process at a time (.shellflow.lock) and no file is "
      "written through a symbolic or hard link there (docs/output.md). Exit codes: 0 done; 1 an error "
      "(one line 'shellflow: error: ...'); 2 a bad command line; 3 an internal error; 4 a run the physics "
      "stopped (Newton gave up, a negative density, an inverted element); 75 stopped with a checkpoint "
      "(--stop-after, --stop-at-wall, SIGINT, SIGTERM): continue with --restart.");
  cli.fallthrough();  // -v/-q also after the subcommand
  bool verbose = false, quiet = false;
  cli.add_flag("-v,--verbose", verbose, "Print debug messages (and Gmsh's progress)");
  cli.add_flag("-q,--quiet", quiet, "Print warnings and errors only");

  // nan and inf pass CLI::PositiveNumber (nan <= 0 is false): numbers of the command line are finite.
  const CLI::Validator finite(
      [](std::string& text) {
        char* end = nullptr;
        const double x = std::strtod(text.c_str(), &end);
        return std::isfinite(x) ? std::string() : std::string("must be a finite number");
      },
      "FINITE");
  app::CommonOptions options;
  bool json = false;
  auto add_case = [&](CLI::App* sub) {
    sub->add_option("case", options.case_file, "Case file (YAML); see docs/case-format.md")
        ->required()
        ->check(CLI::ExistingFile);
    sub->add_option("--set", options.overrides,
                    "KEY=VALUE: replace a key of the case file (dotted path, YAML value), e.g. --set "
                    "fluid.free_stream.mach=2.1 --set time.end=0.05; repeatable")
        ->allow_extra_args(false)
        ->take_all();
  };
  auto add_output = [&](CLI::App* sub) {
    sub->add_option("-o,--output", options.output_dir,
                    "Output directory (default: the case's output.directory, else out/<name>)");
    sub->add_flag("!--no-plot", options.plot, "Do not make the PNG plots at the end");
  };

  auto* run = cli.add_subcommand("run",
                                 "Run a case: mesh it, integrate in time (shell, flow, mesh motion, or all coupled "
                                 "with a 'coupling' section: panel flutter), write .vtu/.pvd fields, probes.csv and "
                                 "plots (coupled runs: coupling.csv, mesh_quality.csv, flutter.png). Under "
                                 "'mpirun -np N' the flow of a flow or coupled run is split over N MPI ranks "
                                 "(METIS parts; .pvtu frames; the same numbers as one process; docs/parallel.md)");
  add_case(run);
  add_output(run);
  run::StopOptions stop;
  run->add_option("--restart", stop.restart,
                  "OUTDIR or OUTDIR/checkpoint_NNNNNN.ckpt: continue a run from its newest (or that) checkpoint, "
                  "in its folder, bit for bit; the case file must be the same (time.end may grow); see "
                  "docs/restart.md");
  run->add_option("--stop-after", stop.stop_after,
                  "Stop after STEPS steps of this invocation with a checkpoint (exit code 75); continue with "
                  "--restart")
      ->check(CLI::PositiveNumber);
  run->add_option("--stop-at-wall", stop.stop_at_wall,
                  "Stop at the first step boundary after SECONDS of wall time with a checkpoint (exit code 75), "
                  "e.g. before a batch queue's limit")
      ->check(CLI::PositiveNumber & finite);
  auto* mesh = cli.add_subcommand("mesh",
                                  "Mesh a case's geometries (fluid, space and shell meshes): write <mesh>.msh and "
                                  "<mesh>.vtu, print sizes and quality (and, for a coupled case with a flow, the wet "
                                  "wall's cells per lambda_x/M, docs/fluid.md), plot the meshes");
  add_case(mesh);
  add_output(mesh);
  mesh->add_flag("--json", json,
                 "Print one JSON object: per mesh nodes, elements, element_type, min_quality; for a coupled case "
                 "with a flow, \"wet_wall\": the wet wall's cells per lambda_x/M of the shell's first two modes");
  auto* check = cli.add_subcommand("check",
                                   "Validate a case file (keys, types, ranges, files, physical groups) without "
                                   "running it");
  add_case(check);

  app::FlutterOptions flutter_options;
  auto* flutter =
      cli.add_subcommand("flutter",
                         "Linear flutter analysis: the case's shell linearised about its reference state with "
                         "first-order piston theory at the case's free stream; root locus against lambda = "
                         "rho U^2 a^3/(beta D) or Mach, the critical point (flutter_locus.csv, flutter.json, "
                         "flutter_locus.png), the first in-vacuo modes and the flutter mode (flutter_modes.vtu, "
                         "flutter_modes.png); see docs/flutter.md");
  add_case(flutter);
  add_output(flutter);
  flutter
      ->add_option("--parameter", flutter_options.parameter,
                   "lambda: sweep lambda at the case's density and Mach; mach: sweep Mach at the case's "
                   "density and pressure")
      ->transform(CLI::CheckedTransformer(std::map<std::string, coupling::FlutterParameter>{
          {"lambda", coupling::FlutterParameter::lambda}, {"mach", coupling::FlutterParameter::mach}}));
  flutter
      ->add_option("--range", flutter_options.range,
                   "LO HI of the parameter (default: lambda 0..max(1000, 2 lambda_case), Mach "
                   "1.2..max(3, 2 M_case), widened up to 8x until a boundary is found)")
      ->check(finite);
  flutter
      ->add_option("--points", flutter_options.points,
                   "Parameter values of the sweep (the boundary is then "
                   "bisected)")
      ->check(CLI::Range(2, 100000));
  flutter
      ->add_option("--modes", flutter_options.modes,
                   "In-vacuo modes of the reduced basis, 2 to 400 (flutter is the coalescence of two modes)")
      ->check(CLI::Validator(
          [](const std::string& text) -> std::string {
            int n = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
            if (ec != std::errc() || end != text.data() + text.size() || n < 2 || n > 400)
              return "expected a whole number of modes from 2 to 400 (flutter is the coalescence of two modes; "
                     "the default is 24), got '" +
                     text + "'";
            return {};
          },
          "INT in [2, 400]"));
  flutter->add_flag("--direct", flutter_options.direct,
                    "Solve the full system (every free dof) instead of the modal basis: dense, O(n^3) per "
                    "value; for checking the basis on small meshes");
  flutter->add_flag("--no-aero-damping", flutter_options.no_aerodynamic_damping,
                    "Drop the aerodynamic damping (mu/M -> 0: the classical coalescence boundary)");
  flutter->add_flag("--json", flutter_options.json,
                    "Print one JSON object on stdout (lambda_cr, mach_cr, frequency_hz, ...) and nothing else");

  int partition_parts = 0;
  auto* partition = cli.add_subcommand("partition",
                                       "Split the case's fluid mesh into parts (METIS) as a distributed run would: "
                                       "print each part's owned and ghost nodes and cells, neighbours and interface "
                                       "nodes, the halo share and the imbalance; write partition.json and "
                                       "partition.vtu (cell field rank, point field owner)");
  add_case(partition);
  partition->add_option("-o,--output", options.output_dir,
                        "Output directory (default: the case's output.directory, else out/<name>)");
  partition->add_option("--parts", partition_parts, "Number of parts (ranks)")
      ->required()
      ->check(CLI::Range(1, 1 << 24));

  app::StudyOptions study_options;
  auto* study =
      cli.add_subcommand("study",
                         "Parameter study of a coupled case (its 'study' section: Mach, density, dynamic pressure "
                         "or thickness over a range): one run per point, growth rates from response.json, the "
                         "stability boundary bracketed and refined; study.csv, study.json, study_growth.png, "
                         "study_lco.png; finished points are not rerun");
  add_case(study);
  add_output(study);
  study
      ->add_option("-j,--jobs", study_options.jobs,
                   "Runs at once, one process each (each with one OpenMP thread "
                   "when > 1 unless OMP_NUM_THREADS is set)")
      ->check(CLI::Range(1, 256));
  study->add_flag("--json", study_options.json, "Print study.json on stdout and nothing else");

  CLI11_PARSE(cli, argc, argv);
  spdlog::set_level(verbose ? spdlog::level::debug : quiet ? spdlog::level::warn : spdlog::level::info);
  // Started by mpirun with several ranks (the launcher says so in the environment): `run`
  // distributes a flow over them (docs/parallel.md); MPI is started for that only, so a plain
  // `shellflow run` is one process without MPI. Rank 0 alone logs, prints errors and writes the
  // output folder (core/output_file.h).
  const int launched_ranks = launcher_ranks();
  bool print_errors = true;
  if (launched_ranks > 1) {
    if (!*run) {
      if (launcher_rank() == 0)
        std::fprintf(stderr,
                     "shellflow: error: started as %d MPI ranks; only 'shellflow run' runs on several ranks "
                     "(docs/parallel.md): run this command without mpirun\n",
                     launched_ranks);
      return 1;
    }
    options.ranks = &dist::Communicator::world();
    if (options.ranks->rank() != 0) {
      set_process_writes_files(false);
      spdlog::set_level(spdlog::level::off);
      print_errors = false;
    }
  }
  try {
    // A bad SHELLFLOW_SIMD is refused before anything is read or meshed.
    spdlog::debug("element pass: {}", fluid::to_string(fluid::simd_path()));
    if (*run) return app::run_command(options, stop);
    if (*mesh) return app::mesh_command(options, json);
    if (*check) return app::check_command(options);
    if (*flutter) return app::flutter_command(options, flutter_options);
    if (*study) return app::study_command(options, study_options);
    if (*partition) return app::partition_command(options, partition_parts);
  } catch (const SolverError& e) {
    if (print_errors) std::fprintf(stderr, "shellflow: error: %s\n", e.what());
    return app::kSolverFailedExitCode;
  } catch (const Error& e) {
    if (print_errors) std::fprintf(stderr, "shellflow: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    if (print_errors) std::fprintf(stderr, "shellflow: internal error: %s\n", e.what());
    return 3;
  }
  return 0;
}
