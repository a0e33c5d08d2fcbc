#include "shellflow/mpi/communicator.h"

#include <fmt/format.h>
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "shellflow/core/error.h"

namespace shellflow::mpi {
namespace {

void check(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw Error(std::string("MPI: ") + what + ": " + std::string(text, std::size_t(length)));
}

/// MPI_Finalize when the process ends normally (a static's destructor).
struct Finaliser {
  ~Finaliser() {
    int initialised = 0, finalised = 0;
    MPI_Initialized(&initialised);
    MPI_Finalized(&finalised);
    if (initialised && !finalised) MPI_Finalize();
  }
};

}  // namespace

Communicator::Communicator() {
  int initialised = 0;
  check(MPI_Initialized(&initialised), "MPI_Initialized");
  if (!initialised) {
    int provided = 0;
    check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    static Finaliser finaliser;
  }
  check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
  check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
  static MPI_Comm exit_comm = MPI_COMM_NULL;
  if (exit_comm == MPI_COMM_NULL) check(MPI_Comm_dup(MPI_COMM_WORLD, &exit_comm), "MPI_Comm_dup");
  exit_comm_ = &exit_comm;
}

Communicator& Communicator::world() {
  static Communicator world;
  return world;
}

namespace {
/// op over the ranks' values of one number.
template <class T>
T all_reduce(T value, MPI_Datatype type, MPI_Op op, const char* what) {
  T out = value;
  check(MPI_Allreduce(&value, &out, 1, type, op, MPI_COMM_WORLD), what);
  return out;
}
}  // namespace

double Communicator::min(double value) const { return all_reduce(value, MPI_DOUBLE, MPI_MIN, "MPI_Allreduce (min)"); }

double Communicator::max(double value) const { return all_reduce(value, MPI_DOUBLE, MPI_MAX, "MPI_Allreduce (max)"); }

long Communicator::sum(long value) const { return all_reduce(value, MPI_LONG, MPI_SUM, "MPI_Allreduce (sum)"); }

bool Communicator::any(bool value) const {
  return all_reduce(value ? 1 : 0, MPI_INT, MPI_LOR, "MPI_Allreduce (or)") != 0;
}

std::vector<double> Communicator::all_gather(const std::vector<double>& values) const {
  const int count = static_cast<int>(values.size());
  std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_) + 1, 0);
  check(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather (counts)");
  for (std::size_t r = 0; r < counts.size(); ++r) offsets[r + 1] = offsets[r] + counts[r];
  std::vector<double> out(std::size_t(offsets.back()));
  check(MPI_Allgatherv(values.data(), count, MPI_DOUBLE, out.data(), counts.data(), offsets.data(), MPI_DOUBLE,
                       MPI_COMM_WORLD),
        "MPI_Allgatherv");
  return out;
}

std::vector<double> Communicator::gather(const std::vector<double>& values, int root) const {
  const int count = static_cast<int>(values.size());
  std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_) + 1, 0);
  check(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, root, MPI_COMM_WORLD), "MPI_Gather (counts)");
  for (std::size_t r = 0; r < counts.size(); ++r) offsets[r + 1] = offsets[r] + counts[r];
  std::vector<double> out(rank_ == root ? std::size_t(offsets.back()) : 0);
  check(MPI_Gatherv(values.data(), count, MPI_DOUBLE, out.data(), counts.data(), offsets.data(), MPI_DOUBLE, root,
                    MPI_COMM_WORLD),
        "MPI_Gatherv");
  return out;
}

double Communicator::sum_in_rank_order(double value) const {
  double total = 0.0;
  for (const double v : all_gather({value})) total += v;
  return total;
}

void Communicator::broadcast(std::string& text, int root) const {
  long length = static_cast<long>(text.size());
  check(MPI_Bcast(&length, 1, MPI_LONG, root, MPI_COMM_WORLD), "MPI_Bcast (length)");
  text.resize(std::size_t(length));
  if (length > 0) check(MPI_Bcast(text.data(), int(length), MPI_CHAR, root, MPI_COMM_WORLD), "MPI_Bcast");
}

bool Communicator::all_leave_within(double seconds) const {
  MPI_Comm comm = *static_cast<MPI_Comm*>(exit_comm_);
  MPI_Request request = MPI_REQUEST_NULL;
  check(MPI_Ibarrier(comm, &request), "MPI_Ibarrier");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  for (;;) {
    int done = 0;
    check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), "MPI_Test");
    if (done) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;  // the request is left: the job ends
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

void Communicator::abort_job(int code) const {
  std::fflush(nullptr);
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);  // MPI_Abort does not return; should it, the process still ends
}

void Communicator::barrier() const { check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier"); }

std::string Communicator::first_error(const std::string& mine) const {
  // The lowest rank with an error, then its message from there.
  const int first = all_reduce(mine.empty() ? size_ : rank_, MPI_INT, MPI_MIN, "MPI_Allreduce (errors)");
  if (first == size_) return {};
  std::string message = rank_ == first ? mine : std::string();
  broadcast(message, first);
  return message;
}

void gather_from_owners(const Communicator& comm, std::span<const int> owner, std::span<double> values,
                        int components) {
  const auto nc = std::size_t(components);
  if (values.size() != owner.size() * nc)
    throw Error(fmt::format("gather_from_owners: {} values for {} entries of {} components", values.size(),
                            owner.size(), components));
  std::vector<double> mine;
  for (std::size_t k = 0; k < owner.size(); ++k)
    if (owner[k] == comm.rank())
      mine.insert(mine.end(), values.begin() + std::ptrdiff_t(k * nc), values.begin() + std::ptrdiff_t((k + 1) * nc));
  const std::vector<double> all = comm.all_gather(mine);
  // Rank r's entries follow those of the ranks before it, each rank's in entry order.
  std::vector<std::size_t> next(std::size_t(comm.size()) + 1, 0);
  for (const int r : owner) next[std::size_t(r) + 1] += nc;
  for (std::size_t r = 1; r < next.size(); ++r) next[r] += next[r - 1];
  if (next.back() != all.size())
    throw Error(fmt::format("gather_from_owners: {} values gathered, {} expected", all.size(), next.back()));
  for (std::size_t k = 0; k < owner.size(); ++k) {
    std::size_t& from = next[std::size_t(owner[k])];
    std::copy_n(all.begin() + std::ptrdiff_t(from), nc, values.begin() + std::ptrdiff_t(k * nc));
    from += nc;
  }
}

}  // namespace shellflow::mpi
