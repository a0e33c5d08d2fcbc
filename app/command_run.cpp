// `shellflow run`: read the case, hand it to the run library (run/run.h).
#include <CLI/CLI.hpp>
#include <memory>
#include <optional>

#include "commands.h"
#include "shellflow/mpi/communicator.h"
#include "shellflow/run/run.h"

namespace shellflow::app {

io::Case read_case(const CommonOptions& options) {
  std::vector<io::KeyOverride> overrides;
  for (const auto& text : options.overrides) overrides.push_back(io::KeyOverride::parse(text));
  return io::read_case(options.case_file, overrides);
}

int run_command(const CommonOptions& options, const StopOptions& stop) {
  // On ranks every rank reads the case: an error that only some see (a --set on one part of
  // an MPMD line, a case file missing on one node) ends every rank with the first one's line.
  std::optional<io::Case> read;
  mpi::on_every_rank(options.ranks, [&] { read.emplace(read_case(options)); });
  const io::Case& c = *read;
  return run::run_case(c, {.case_file = options.case_file,
                           .output_dir = options.output_dir,
                           .plot = options.plot,
                           .stop = stop,
                           .ranks = options.ranks});
}

Command add_run_command(CLI::App& cli, CommonOptions& common) {
  auto stop = std::make_shared<StopOptions>();
  auto* sub = cli.add_subcommand("run",
                                 "Run a case: mesh it, integrate in time (shell, flow, mesh motion, or all coupled "
                                 "with a 'coupling' section: panel flutter), write .vtu/.pvd fields, probes.csv and "
                                 "plots (coupled runs: coupling.csv, mesh_quality.csv, flutter.png). Under "
                                 "'mpirun -np N' the flow of a flow or coupled run is split over N MPI ranks "
                                 "(METIS parts; .pvtu frames; the same numbers as one process; docs/parallel.md)");
  add_case_options(sub, common);
  add_output_options(sub, common);
  sub->add_option("--restart", stop->restart,
                  "OUTDIR or OUTDIR/checkpoint_NNNNNN.ckpt: continue a run from its newest (or that) checkpoint, "
                  "in its folder, bit for bit; the case file must be the same (time.end may grow); see "
                  "docs/restart.md");
  sub->add_option("--stop-after", stop->stop_after,
                  "Stop after STEPS steps of this invocation with a checkpoint (exit code 75); continue with "
                  "--restart")
      ->check(CLI::PositiveNumber);
  sub->add_option("--stop-at-wall", stop->stop_at_wall,
                  "Stop at the first step boundary after SECONDS of wall time with a checkpoint (exit code 75), "
                  "e.g. before a batch queue's limit")
      ->check(CLI::PositiveNumber & finite_number());
  return {sub, [&common, stop] { return run_command(common, *stop); }};
}

}  // namespace shellflow::app
