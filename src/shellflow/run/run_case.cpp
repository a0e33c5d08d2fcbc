#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "shellflow/io/case_meshes.h"
#include "shellflow/run/run.h"
#include "shellflow/run/run_kinds.h"

namespace shellflow::run {
namespace {

/// The output folder: a new run's (created), or the folder of the checkpoint a restart
/// continues; locked either way. Every refusal comes before anything is written there.
OutputFolder output_folder(const io::Case& c, const RunOptions& options, std::optional<io::Checkpoint>& checkpoint) {
  namespace fs = std::filesystem;
  if (!options.stop.restart) return prepare_output_dir(c, options.output_dir);
  const fs::path& restart = *options.stop.restart;
  std::error_code ec;
  fs::path outdir = fs::is_directory(restart, ec) ? restart : restart.parent_path();
  if (outdir.empty()) outdir = ".";
  if (options.output_dir && fs::weakly_canonical(*options.output_dir) != fs::weakly_canonical(outdir))
    throw Error(
        fmt::format("--restart {} continues the run in {}; drop -o {} (a restart writes into the folder of its "
                    "checkpoint)",
                    restart.string(), outdir.string(), options.output_dir->string()));
  // A missing folder: load_restart says what is missing. Otherwise the folder is locked before
  // the checkpoint is read.
  if (!fs::is_directory(outdir, ec)) checkpoint = load_restart(restart, c);
  OutputFolder folder = open_output_dir(outdir);
  checkpoint = load_restart(restart, c);
  return folder;
}

/// The kind of run the case's sections ask for.
void run_kind(const RunContext& run) {
  const io::Case& c = run.c;
  if (c.coupling) {
    if (c.coupling->identification)
      run_identification(run);  // the flow driven by the shell's modes, no shell solve
    else
      run_coupled(run);  // shell and flow (or piston theory, or only the fluid mesh) together
  } else if (c.motion) {
    run_mesh_motion(run);  // prescribed boundary motion, no flow: the mesh-motion tests
  } else if (c.shell && c.shell->analysis) {
    run_shell(run);
  } else if (c.fluid && c.fluid->analysis) {
    run_fluid(run);
  } else {
    run.control.not_time_stepping("a case without an analysis");
    run.recorder.record(0, 0.0, Record::probes_and_fields);
    spdlog::warn(
        "nothing to integrate: the case has no 'motion', 'shell.analysis' or 'fluid.analysis' (or a "
        "'coupling' section); wrote the initial state (t = 0) only");
  }
}

/// What a run on several ranks can do (docs/parallel.md): a flow run or a coupled run. A
/// mesh-motion run, a shell run or a case without an analysis is refused with one line, the
/// same on every rank, before anything is written.
void check_distributable(const io::Case& c, const RunOptions& options) {
  const int n = options.ranks->size();
  const char* kind = c.motion && !c.coupling                          ? "a mesh-motion run"
                     : c.shell && c.shell->analysis && !c.coupling    ? "a shell run"
                     : !c.coupling && !(c.fluid && c.fluid->analysis) ? "a case without an analysis"
                                                                      : nullptr;
  if (kind)
    throw InputError(fmt::format(
        "{}: {} does not run on {} MPI ranks (flow runs and coupled runs do; docs/parallel.md): run it without mpirun",
        c.file.string(), kind, n));
}

/// `text` split at `sep`.
std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> out;
  std::size_t from = 0;
  for (std::size_t at; (at = text.find(sep, from)) != std::string::npos; from = at + 1)
    out.push_back(text.substr(from, at - from));
  out.push_back(text.substr(from));
  return out;
}

/// Every rank runs rank 0's case into rank 0's folder: a rank whose case differs (a stale
/// copy of the case file on its node, other --set options on its part of an MPMD line) or
/// whose -o or --restart differs is refused with one line, the same on every rank.
void check_same_run_on_every_rank(const io::Case& c, const RunOptions& options) {
  const mpi::Communicator& ranks = *options.ranks;
  std::string digests;
  for (const io::SectionDigest& d : c.digests) digests += fmt::format("{}={:016x};", d.name, d.digest);
  const auto path_of = [](const std::optional<std::filesystem::path>& p) { return p ? p->string() : std::string("-"); };
  std::string mine = digests + '\n' + path_of(options.output_dir) + '\n' + path_of(options.stop.restart);
  std::string first = mine;
  ranks.broadcast(first);
  std::string why;
  if (mine != first) {
    const std::vector<std::string> a = split(mine, '\n'), b = split(first, '\n');
    if (a.at(0) != b.at(0)) {
      const std::vector<std::string> sa = split(a[0], ';'), sb = split(b[0], ';');
      std::string section = "its sections";
      for (std::size_t i = 0; i < std::max(sa.size(), sb.size()); ++i)
        if (i >= sa.size() || i >= sb.size() || sa[i] != sb[i]) {
          section = "section '" + split(i < sa.size() ? sa[i] : sb[i], '=').at(0) + "'";
          break;
        }
      why = fmt::format(
          "{}: rank {} read another case than rank 0 ({} differ(s): a stale copy of the case file on its node, or "
          "other --set options on its part of the command line); every rank must run the same case",
          c.file.string(), ranks.rank(), section);
    } else if (a.at(1) != b.at(1)) {
      why = fmt::format(
          "rank {} was given -o {}, rank 0 -o {}: every rank must write to the same folder; give them "
          "the same -o",
          ranks.rank(), a[1], b[1]);
    } else {
      why = fmt::format("rank {} was given --restart {}, rank 0 --restart {}: give every rank the same --restart",
                        ranks.rank(), a.at(2), b.at(2));
    }
  }
  if (const std::string first_why = ranks.first_error(why); !first_why.empty()) throw InputError(first_why);
}

}  // namespace

int run_case(const io::Case& c, const RunOptions& options) {
  const mpi::Communicator* ranks = options.ranks;
  const bool root = !ranks || ranks->rank() == 0;
  if (ranks) {
    check_same_run_on_every_rank(c, options);
    check_distributable(c, options);
  }
  // 1. The output folder and the meshes, from the folder's mesh cache while their inputs are
  // unchanged (a restart reads the cache but saves nothing: the folder keeps the run's own).
  // On ranks, rank 0 makes the folder and meshes; the others then read its mesh cache.
  std::optional<io::Checkpoint> checkpoint;
  OutputFolder folder;
  std::optional<io::CaseMeshes> meshes;
  const auto load = [&] {
    folder = output_folder(c, options, checkpoint);
    meshes.emplace(checkpoint ? io::load_case_meshes(c, std::nullopt, folder.path)  // reads the cache
                              : io::load_case_meshes(c, folder.path));
  };
  mpi::on_every_rank(ranks, [&] {
    if (root) load();
  });
  if (ranks) {
    std::string path = folder.path.string();
    ranks->broadcast(path);
    folder.path = path;
    mpi::on_every_rank(ranks, [&] {
      if (root) return;
      if (options.stop.restart) checkpoint = load_restart(*options.stop.restart, c);
      meshes.emplace(io::load_case_meshes(c, std::nullopt, folder.path));
    });
  }
  const std::filesystem::path& outdir = folder.path;
  spdlog::info("case '{}' -> {}{}", c.name, outdir.string(),
               ranks ? fmt::format(" ({} MPI ranks)", ranks->size()) : std::string());
  // A stop signal during the meshing: stop before the solvers are built (no step was made, so
  // no checkpoint is needed; the meshes stay in the folder's cache for the next start).
  if (stop_signal_received(ranks)) {
    spdlog::warn(
        "stopped on a signal during the set-up, before the first step: nothing to checkpoint; run the "
        "same command again to {}",
        options.stop.restart ? "continue from " + checkpoint->file.string() : std::string("start the run"));
    return kStoppedExitCode;
  }
  // 2. The checkpoint control; only now, with the case read and meshed, the earlier run's
  // output goes (a case with an error keeps the old results; not for `study`, whose folder
  // holds the points of a study to resume).
  std::vector<io::SectionDigest> digests = c.digests;
  for (const mesh::Mesh* m : meshes->all()) digests.push_back(io::mesh_digest(*m));
  RunControl control(c, outdir, options.stop, std::move(checkpoint), std::move(digests), ranks);
  if (!control.restarting() && root) remove_previous_run_output(outdir);
  // 3. The recorder and the run.
  Recorder recorder(c, *meshes, outdir, control.output_mode());
  PlotJobs plots;
  const auto start = std::chrono::steady_clock::now();
  run_kind({c, *meshes, outdir, control, recorder, plots, ranks});
  control.log_summary(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  spdlog::info("wrote {}: <mesh>_NNNNNN.{}, <mesh>.pvd, probes.csv", outdir.string(),
               ranks ? "pvtu (+ one .vtu piece per rank)" : "vtu");
  // 4. The plots (rank 0): the probes first, then the run kind's.
  if (options.plot && root) {
    plots.insert(plots.begin(), {"plot_probes.py", probe_plot_arguments(c, outdir)});
    make_plots(plots);
  }
  if (!control.stopped()) return 0;
  spdlog::warn("{}", control.stopped_message(options.case_file));
  return kStoppedExitCode;
}

}  // namespace shellflow::run
