#include "shellflow/run/run_control.h"

#include <omp.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <ctime>
#include <set>

#include "shellflow/core/error.h"
#include "shellflow/core/output_file.h"
#include "shellflow/core/version.h"
#include "shellflow/fluid/residual.h"
#include "shellflow/run/output_dir.h"

namespace shellflow::run {
namespace fs = std::filesystem;
namespace {

volatile std::sig_atomic_t g_stop_signal = 0;
bool g_armed_for_the_process = false;    // arm_stop_signals()
volatile std::sig_atomic_t g_quiet = 0;  // quiet_stop_signals()
timespec g_first_signal{};               // when the first one came (CLOCK_MONOTONIC)

extern "C" void on_stop_signal(int sig) {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);  // async-signal-safe
  if (g_stop_signal != 0) {
    // A second one within a second is the same request arriving twice (a terminal's Ctrl-C
    // reaches a study's runs and the study passes its own on); later: stop now.
    const double since =
        double(now.tv_sec - g_first_signal.tv_sec) + 1e-9 * double(now.tv_nsec - g_first_signal.tv_nsec);
    if (since < 1.0) return;
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  g_first_signal = now;
  g_stop_signal = sig;
  if (g_quiet != 0) return;  // the command has ended
  constexpr char message[] =
      "\nshellflow: stopping after the current step with a checkpoint (signal again after a second to stop at "
      "once)\n";
  if (!process_writes_files()) return;  // ranks other than 0 (one line per job)
  [[maybe_unused]] const auto n = ::write(STDERR_FILENO, message, sizeof(message) - 1);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void install_stop_handler(struct sigaction* old_int, struct sigaction* old_term, struct sigaction* old_usr1) {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, old_int);
  sigaction(SIGTERM, &action, old_term);
  sigaction(SIGUSR1, &action, old_usr1);
}

}  // namespace

void arm_stop_signals() {
  if (g_armed_for_the_process) return;
  install_stop_handler(nullptr, nullptr, nullptr);
  g_armed_for_the_process = true;
}

void quiet_stop_signals() { g_quiet = 1; }

bool stop_signal_received(const mpi::Communicator* ranks) {
  const bool here = g_stop_signal != 0;
  return ranks ? ranks->any(here) : here;
}

std::chrono::steady_clock::time_point process_start() {
  static const auto start = std::chrono::steady_clock::now();
  return start;
}

io::CheckpointHeader current_header(const io::Case& c, std::vector<io::SectionDigest> digests) {
  io::CheckpointHeader h;
  h.program_version = shellflow::version;
  h.build = io::executable_build_id();
  h.case_name = c.name;
  h.threads = omp_get_max_threads();
  h.simd = std::string(fluid::to_string(fluid::simd_path()));
  h.digests = std::move(digests);
  return h;
}

io::Checkpoint load_restart(const fs::path& path, const io::Case& c) {
  io::Checkpoint checkpoint = io::read_checkpoint(io::find_checkpoint(path));
  // The meshes are compared once they are made (RunControl): here the case file only.
  std::vector<io::SectionDigest> digests = c.digests;
  for (const auto& d : checkpoint.header.digests)
    if (d.name.starts_with("mesh ")) digests.push_back(d);
  if (const std::string why = io::checkpoint_mismatch(checkpoint, current_header(c, digests)); !why.empty())
    throw Error(why);
  // A restart continues a run: its checkpoint lies at or before time.end (refused before
  // anything is set up or written; the time loop checks the step once it knows the steps). A
  // checkpoint at time.end finishes a run killed before its end-of-run files.
  const io::CheckpointHeader& then = checkpoint.header;
  if (c.time && then.time > c.time->end * (1.0 + 1e-9))
    throw Error(fmt::format(
        "{}: step {} (t = {:.6g} s) is after time.end = {:.6g} s of this run; raise time.end (--set time.end=...) to "
        "continue it",
        checkpoint.file.string(), then.step, then.time, c.time->end));
  return checkpoint;
}

RunControl::RunControl(const io::Case& c, fs::path outdir, StopOptions options, std::optional<io::Checkpoint> restart,
                       std::vector<io::SectionDigest> digests, const mpi::Communicator* ranks)
    : case_(c),
      outdir_(std::move(outdir)),
      options_(std::move(options)),
      restart_(std::move(restart)),
      digests_(std::move(digests)),
      every_(c.output.checkpoint_every),
      start_(process_start()) {
  ranks_ = ranks;
  if (restart_) {
    const io::CheckpointHeader now = current_header(c, digests_);
    if (const std::string why = io::checkpoint_mismatch(*restart_, now); !why.empty()) throw Error(why);
    const io::CheckpointHeader& then = restart_->header;
    if (then.build != now.build)
      spdlog::warn(
          "{}: written by another build of shellflow {}; the continuation may differ from an "
          "uninterrupted run in the last bits",
          restart_->file.string(), then.program_version);
    // The thread count is recorded but not compared: the run's sums do not depend on it
    // (core/parallel.h).
    if (then.simd != now.simd)
      spdlog::warn(
          "{}: written with the {} element pass, this run uses {}; the flow may differ from an "
          "uninterrupted run in the last bits (set SHELLFLOW_SIMD={})",
          restart_->file.string(), then.simd, now.simd, then.simd);
    spdlog::info("restart from {}: step {}, t = {:.6g} s", restart_->file.string(), then.step, then.time);
  }
}

void RunControl::arm_signals() {
  if (armed_ || g_armed_for_the_process) return;  // armed for the process: a signal of the set-up counts
  g_stop_signal = 0;
  install_stop_handler(&old_int_, &old_term_, &old_usr1_);
  armed_ = true;
}

RunControl::~RunControl() {
  if (!armed_) return;
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
  sigaction(SIGUSR1, &old_usr1_, nullptr);
}

void RunControl::not_time_stepping(std::string_view what) const {
  if (restart_)
    throw Error(fmt::format("{}: {} is not checkpointed (it does not step in time); run it without --restart",
                            restart_->file.string(), what));
  if (options_.stop_after || options_.stop_at_wall || every_ > 0)
    spdlog::warn("{} is not checkpointed: --stop-after, --stop-at-wall and output.checkpoint_every are ignored", what);
}

void RunControl::set_state(std::string kind, std::function<void(ArchiveWriter&)> save,
                           std::function<void(ArchiveReader&)> restore) {
  kind_ = std::move(kind);
  save_ = std::move(save);
  restore_ = std::move(restore);
}

void RunControl::restore(const std::function<double()>& time, long steps, double end_time) {
  if (!restart_) return;
  ArchiveReader in(restart_->payload, restart_->file.string());
  const std::string kind = in.get_string();
  if (kind != kind_)
    throw Error(fmt::format("{}: a checkpoint of a {} run, this case is a {} run", in.what(), kind, kind_));
  const long step = in.get<long>();
  if (step != restart_->header.step) throw Error(in.what() + ": damaged (two different steps)");
  const auto outputs = in.get<std::uint64_t>();
  in.expect_size("the output files", outputs, outputs_.size());
  std::set<std::string> listed;
  for (const auto& w : outputs_) {
    std::visit([&](auto* writer) { writer->restore(in); }, w);
    if (const auto* pvd = std::get_if<io::PvdWriter*>(&w))
      for (const auto& e : (*pvd)->entries()) listed.insert(e.file);
  }
  if (restore_) restore_(in);
  in.expect_end();
  // The restored state's time is the header's, and (fixed steps) that of its step.
  const io::CheckpointHeader& h = restart_->header;
  if (time) {
    const double t = time();
    if (t != h.time)
      throw Error(
          fmt::format("{}: damaged (the header says t = {:.17g} s, the state t = {:.17g} s)", in.what(), h.time, t));
    const double dt = steps > 0 ? end_time / double(steps) : 0.0;
    if (steps > 0 && !(std::abs(t - double(h.step) * dt) <= dt))
      throw Error(fmt::format("{}: damaged (t = {:.6g} s at step {}, but step {} of this run is at t = {:.6g} s)",
                              in.what(), t, h.step, h.step, double(h.step) * dt));
  }
  // Frames after the checkpoint (a killed run's, or the last frame of a stopped run that is
  // not in the series) are written again or were never part of the uninterrupted run.
  // The .tmp files of writes a kill interrupted go too.
  std::error_code ec;
  std::vector<fs::path> later;
  for (fs::directory_iterator it(outdir_, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (it->symlink_status(ec).type() != fs::file_type::regular) continue;
    const auto frame = frame_file(name);
    if ((frame && (frame->step > step || (frame->step == step && !listed.contains(frame->entry)))) ||
        (name.ends_with(".tmp") && is_run_output_name(name)))
      later.push_back(it->path());
  }
  std::size_t removed = 0;
  if (!process_writes_files()) later.clear();  // a distributed run's other ranks: rank 0 removes them
  for (const fs::path& p : later) removed += fs::remove(p, ec) ? 1 : 0;
  if (removed > 0) spdlog::info("restart: removed {} file(s) written after the checkpoint", removed);
  restored_ = true;
}

bool RunControl::stop_due(long steps_done) const {
  const bool here = g_stop_signal != 0 || (options_.stop_after && steps_done >= *options_.stop_after) ||
                    (options_.stop_at_wall && seconds_since(start_) >= *options_.stop_at_wall);
  return ranks_ ? ranks_->any(here) : here;
}

void RunControl::write_checkpoint(long step, double time) {
  const auto t0 = std::chrono::steady_clock::now();
  ArchiveWriter out;
  out.put(kind_);
  out.put(step);
  out.put(static_cast<std::uint64_t>(outputs_.size()));
  for (const auto& w : outputs_) std::visit([&](const auto* writer) { writer->save(out); }, w);
  if (save_) save_(out);
  io::CheckpointHeader header = current_header(case_, digests_);
  header.step = step;
  header.time = time;
  const std::uint64_t bytes = io::write_checkpoint(outdir_, header, out.bytes());
  const double s = seconds_since(t0);
  ++written_;
  seconds_ += s;
  largest_seconds_ = std::max(largest_seconds_, s);
  bytes_ = bytes;
  last_file_ = io::checkpoint_path(outdir_, step);
  spdlog::debug("checkpoint {} ({:.1f} MB, {:.1f} ms)", last_file_->string(), double(bytes) / 1e6, 1e3 * s);
}

void RunControl::mark_stopped(long step, double time) {
  stopped_step_ = step;
  stopped_time_ = time;
}

std::string RunControl::stopped_message(const fs::path& case_file) const {
  const char* why = g_stop_signal == SIGINT    ? "on SIGINT"
                    : g_stop_signal == SIGTERM ? "on SIGTERM"
                    : g_stop_signal == SIGUSR1 ? "on SIGUSR1"
                    : options_.stop_after && *stopped_step_ - first_step() + 1 >= *options_.stop_after
                        ? "after --stop-after steps"
                        : "at --stop-at-wall";
  return fmt::format(
      "stopped {} at step {} (t = {:.6g} s) with checkpoint {}; continue with: shellflow run {} "
      "--restart {}",
      why, *stopped_step_, stopped_time_, last_file_ ? last_file_->string() : "(none)", case_file.string(),
      outdir_.string());
}

void RunControl::log_summary(double run_seconds) const {
  if (written_ == 0) return;
  spdlog::info("checkpoints: {} written ({:.1f} MB each, {:.1f} ms mean, {:.1f} ms at most; {:.2f} % of the run)",
               written_, double(bytes_) / 1e6, 1e3 * seconds_ / written_, 1e3 * largest_seconds_,
               run_seconds > 0 ? 100.0 * seconds_ / run_seconds : 0.0);
}

}  // namespace shellflow::run
