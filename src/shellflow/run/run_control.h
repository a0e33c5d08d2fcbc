#pragma once
// Checkpoints, stops and restarts of a run (docs/restart.md), for every kind of run through
// the one time loop (time_loop.h).
//
// A run kind (shell_run, fluid_run, motion_run, coupled_run) registers its output writers
// (add_output) and the functions that save and restore its state (set_state), then calls
// restore() once it is set up: on a restarted run that puts every writer and the state back
// to the checkpoint. The loop asks checkpoint_due / stop_due after every step.
//
// A checkpoint's payload: kind, step, the writers' positions in registration order, then the
// run kind's state.
#include <chrono>
#include <csignal>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "shellflow/core/archive.h"
#include "shellflow/io/case.h"
#include "shellflow/io/checkpoint.h"
#include "shellflow/io/probe_writer.h"
#include "shellflow/io/pvd_writer.h"
#include "shellflow/mpi/communicator.h"

namespace shellflow::run {

/// The exit code of a run that stopped with a checkpoint (--stop-after, --stop-at-wall,
/// SIGINT/SIGTERM): EX_TEMPFAIL, "try again later".
inline constexpr int kStoppedExitCode = 75;

/// Installs the SIGINT/SIGTERM/SIGUSR1 handler of RunControl for the rest of the process
/// (`shellflow run` does first thing): a signal during the set-up is kept, and the run stops at
/// the first point that can stop (after the meshing, or the first step boundary) instead of
/// dying where it stands. SIGUSR1 is the stop signal of MPI jobs: mpirun passes it on to every
/// rank and lets the job end with the ranks' exit code (75), where SIGINT/SIGTERM make it kill
/// the ranks a second later and exit 1 (docs/parallel.md).
void arm_stop_signals();
/// Once the command has ended: a stop signal is still caught (a launcher that ends the other
/// ranks of a job when one leaves with an error sends SIGTERM) but announces no stop, because
/// there is no step left to stop after; the process goes on to say its error and leave.
void quiet_stop_signals();
/// Whether a stop signal came, on any of `ranks` (null: this process); every rank calls it at
/// the same point.
bool stop_signal_received(const mpi::Communicator* ranks);

/// The exit code of a run the physics stopped (a SolverError: Newton gave up, a negative
/// density, an inverted element): a result of the case, where exit code 1 is an input or
/// system error. A study records the first as a failed point and reruns the second.
inline constexpr int kSolverFailedExitCode = 4;

/// The command line's stop and restart options.
struct StopOptions {
  std::optional<long> stop_after;      ///< steps of this invocation, then a checkpoint and exit
  std::optional<double> stop_at_wall;  ///< wall seconds since the program started, then the same at the next step
  std::optional<std::filesystem::path> restart;  ///< OUTDIR or OUTDIR/checkpoint_NNNNNN.ckpt
};

class RunControl {
 public:
  /// `restart`: the verified checkpoint this run continues (nullopt: a new run). Installs
  /// Throws Error when the checkpoint's meshes differ from this run's (`digests`).
  /// `ranks`: the ranks of a distributed run (null: one process); a stop is then decided on
  /// all of them together (a signal or the wall clock of any rank stops every rank at the same
  /// step).
  RunControl(const io::Case& c, std::filesystem::path outdir, StopOptions options,
             std::optional<io::Checkpoint> restart, std::vector<io::SectionDigest> digests,
             const mpi::Communicator* ranks = nullptr);
  ~RunControl();
  RunControl(const RunControl&) = delete;
  RunControl& operator=(const RunControl&) = delete;

  /// How writers of this run open their files: resume on a restart.
  io::OutputMode output_mode() const { return restart_ ? io::OutputMode::resume : io::OutputMode::create; }
  bool restarting() const { return restart_.has_value(); }
  /// The ranks of a distributed run (null: one process).
  const mpi::Communicator* ranks() const { return ranks_; }
  /// The checkpoint this run continues (null for a new run).
  const io::Checkpoint* restart() const { return restart_ ? &*restart_ : nullptr; }
  /// The first step this invocation makes (1, or the checkpoint's step + 1).
  long first_step() const { return restart_ ? restart_->header.step + 1 : 1; }

  void add_output(io::ProbeWriter& w) { outputs_.emplace_back(&w); }
  void add_output(io::PvdWriter& w) { outputs_.emplace_back(&w); }
  /// The run kind's state. `kind` names it in the checkpoint ("shell dynamics", "flow",
  /// "mesh motion", "coupled"): a checkpoint of another kind is refused.
  void set_state(std::string kind, std::function<void(ArchiveWriter&)> save,
                 std::function<void(ArchiveReader&)> restore);
  /// On a restart: every writer and the state back to the checkpoint, and the frames
  /// (<mesh>_NNNNNN.vtu) written after it removed. Throws Error when the checkpoint does not
  /// fit this run: also when the restored state's `time()` is not the header's, or (with
  /// `steps` > 0 fixed steps up to `end_time`) not that of its step. A no-op for a new run.
  void restore(const std::function<double()>& time = {}, long steps = 0, double end_time = 0.0);
  /// Whether restore() put a restarted run back (false before, and after a refusal): a run
  /// that fails before that writes nothing on its way out.
  bool restored() const { return restored_; }

  /// A run that does not step in time (static, modal): Error on a restart, a warning for
  /// the stop and checkpoint options (`what`: "a static analysis").
  void not_time_stepping(std::string_view what) const;
  /// Installs the SIGINT/SIGTERM/SIGUSR1 handlers (the time loop does, when it starts): a first
  /// signal stops the run at the next step boundary with a checkpoint, a second one more
  /// than a second later ends it at once (one within a second is the same request twice).
  /// The destructor puts the previous handlers back.
  void arm_signals();

  bool checkpoint_due(long step) const { return every_ > 0 && step % every_ == 0; }
  /// Whether the run stops after `steps_done` steps of this invocation (a signal, --stop-after,
  /// --stop-at-wall).
  bool stop_due(long steps_done) const;
  void write_checkpoint(long step, double time);
  void mark_stopped(long step, double time);
  bool stopped() const { return stopped_step_.has_value(); }
  /// The message of a stopped run: where it stopped and how to continue it.
  std::string stopped_message(const std::filesystem::path& case_file) const;
  /// Logs the checkpoints written (count, size, time) at the end of a run.
  void log_summary(double run_seconds) const;

 private:
  const io::Case& case_;
  std::filesystem::path outdir_;
  StopOptions options_;
  const mpi::Communicator* ranks_ = nullptr;
  std::optional<io::Checkpoint> restart_;
  std::vector<io::SectionDigest> digests_;
  long every_ = 0;
  std::vector<std::variant<io::ProbeWriter*, io::PvdWriter*>> outputs_;
  std::string kind_;
  std::function<void(ArchiveWriter&)> save_;
  std::function<void(ArchiveReader&)> restore_;
  std::chrono::steady_clock::time_point start_;
  std::optional<long> stopped_step_;
  double stopped_time_ = 0.0;
  int written_ = 0;
  double seconds_ = 0.0, largest_seconds_ = 0.0;
  std::uint64_t bytes_ = 0;
  std::optional<std::filesystem::path> last_file_;
  bool armed_ = false;
  bool restored_ = false;
  struct sigaction old_int_ {
  }, old_term_{}, old_usr1_{};
};

/// The time the program started (main calls it first): --stop-at-wall counts from it.
std::chrono::steady_clock::time_point process_start();

/// The verified checkpoint of --restart PATH for case `c`: read_checkpoint plus the case
/// and version checks (io::checkpoint_mismatch, without the meshes). Throws Error (one line)
/// before anything is written.
io::Checkpoint load_restart(const std::filesystem::path& path, const io::Case& c);
/// The header this run's checkpoints get (version, build, case, threads, digests).
io::CheckpointHeader current_header(const io::Case& c, std::vector<io::SectionDigest> digests);

}  // namespace shellflow::run
