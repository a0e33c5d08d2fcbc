#pragma once
// The MPI ranks of a distributed run (docs/parallel.md): the world communicator, reductions
// whose results do not depend on the number of ranks where they feed the solution, and an
// agreement on errors so that an error on one rank ends every rank with the same line.
//
// MPI is initialised on first use of Communicator::world() (MPI_THREAD_FUNNELED: only the
// thread that calls these functions talks to MPI; the thread pool of core/parallel.h stays
// inside a rank) and finalised when the process exits normally. Without mpirun it is one rank
// (OpenMPI's singleton start).
#include <exception>
#include <span>
#include <string>
#include <vector>

#include "shellflow/core/error.h"

namespace shellflow::mpi {

class Communicator {
 public:
  /// MPI_COMM_WORLD (initialises MPI on the first call).
  static Communicator& world();

  int rank() const { return rank_; }
  int size() const { return size_; }

  /// Smallest / largest of the ranks' values (exact: the same on any rank count).
  double min(double value) const;
  double max(double value) const;
  long sum(long value) const;  ///< integer sum (exact)
  bool any(bool value) const;  ///< logical or
  /// Sum of one double per rank, added in rank order on every rank (the same bits on every
  /// rank; for bits independent of the rank count, sum per fixed chunk first).
  double sum_in_rank_order(double value) const;
  /// Every rank's values, concatenated in rank order.
  std::vector<double> all_gather(const std::vector<double>& values) const;
  /// Every rank's values, concatenated in rank order, on rank `root` (empty on the others).
  std::vector<double> gather(const std::vector<double>& values, int root = 0) const;
  /// `text` of rank `root` on every rank.
  void broadcast(std::string& text, int root = 0) const;
  void barrier() const;

  /// Called by every rank at the same point with its error message ("" = none). Returns ""
  /// when no rank has an error, else the message of the lowest rank that has one, on every
  /// rank: each rank then throws the same error and the run ends on all of them (no rank is
  /// left waiting in a collective).
  std::string first_error(const std::string& mine) const;

  /// Called on the way out of the process with an error: whether every rank reaches this
  /// call within `seconds` (an error they agreed on: they end together). False when some rank
  /// does not come (it waits in a collective for this one, or finished): the caller then ends
  /// the job with abort_job(). Matched on a communicator of its own, so a rank still waiting
  /// in a collective of the run is not disturbed.
  bool all_leave_within(double seconds) const;
  /// Ends every rank of the job (MPI_Abort) with `code`; the launcher reports it.
  [[noreturn]] void abort_job(int code) const;

 private:
  Communicator();
  int rank_ = 0;
  int size_ = 1;
  void* exit_comm_ = nullptr;  ///< MPI_Comm of all_leave_within (a duplicate of the world)
};

/// Entries owned by one rank each, made known to every rank: entry k (`components` values
/// from values[k * components]) belongs to rank owner[k]; on entry each rank holds its own
/// entries (the others any value), on return every rank holds every entry as its owner had it
/// (copied, not summed: the same bits on any rank count). Every rank calls it with the same
/// owners.
void gather_from_owners(const Communicator& comm, std::span<const int> owner, std::span<double> values,
                        int components = 1);

/// Runs `f` on every rank of `comm` (or just runs it when `comm` is null) and agrees on its
/// failure: when f throws on some rank, every rank throws after it, the rank's own exception
/// or Error with the lowest failing rank's line (first_error), so no rank goes on to wait for
/// a failed one. Every rank must call it at the same point.
template <class F>
void on_every_rank(const Communicator* comm, F&& f) {
  if (!comm) {
    f();
    return;
  }
  std::exception_ptr mine;
  std::string message;
  try {
    f();
  } catch (const std::exception& e) {
    mine = std::current_exception();
    message = *e.what() ? e.what() : "error";
  }
  const std::string first = comm->first_error(message);
  if (mine) std::rethrow_exception(mine);
  if (!first.empty()) throw Error(first);
}

}  // namespace shellflow::mpi
