// Ranks against threads on a box flow (issue 21's performance item): the step of
// bench/fluid/bench_fluid_step.cpp (Mach 2 box of n^3 cubes x 6 tets, artificial viscosity on)
// on the ranks' parts of the box (FluidModel::set_distribution, docs/parallel.md). Every rank
// builds and partitions the whole box, steps its part, and rank 0 prints the slowest rank's
// milliseconds per step. Compare in one session:
//   OMP_NUM_THREADS=1 mpiexec -n 1 build/release/bench/mpi/bench_flow_on_ranks 40
//   OMP_NUM_THREADS=2 mpiexec -n 1 build/release/bench/mpi/bench_flow_on_ranks 40
//   OMP_NUM_THREADS=1 mpiexec -n 2 build/release/bench/mpi/bench_flow_on_ranks 40
// (as root: OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1).
// Arguments: n (default 40: 384 000 tets), steps (default 20).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include "../fluid/box_mesh.h"
#include "shellflow/core/parallel.h"
#include "shellflow/fluid/fluid_model.h"
#include "shellflow/fluid/ordering.h"
#include "shellflow/mesh/partition.h"
#include "shellflow/mpi/communicator.h"
#include "shellflow/mpi/flow_distribution.h"
#include "shellflow/mpi/halo_exchange.h"

using namespace shellflow;

int main(int argc, char** argv) {
  auto& comm = mpi::Communicator::world();
  const int n = argc > 1 ? std::atoi(argv[1]) : 40;
  const int steps = argc > 2 ? std::atoi(argv[2]) : 20;
  if (n < 2 || steps < 1) {
    if (comm.rank() == 0) std::fprintf(stderr, "usage: bench_flow_on_ranks [n >= 2] [steps >= 1]\n");
    return 2;
  }
  mesh::Mesh global = fluid::bench::box_mesh(n);
  fluid::renumber_for_locality(global);
  const auto setup_start = std::chrono::steady_clock::now();
  const std::vector<int> cell_part = mesh::partition_cells(global, comm.size());
  const std::vector<int> owner = mesh::node_owners(global, cell_part);
  const mesh::LocalPart part = mesh::make_local_part(global, owner, comm.rank());
  mesh::Mesh local = comm.size() > 1 ? mesh::local_mesh(global, part) : global;
  const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - setup_start).count();
  const long local_cells = local.num_cells();

  fluid::FluidOptions options;
  options.q_dif = 1.0;
  const fluid::Primitive free_stream{1.0, Vec3(2.0, 0.0, 0.0), 1.0 / options.gas.gamma};
  fluid::FluidModel model(std::move(local), options,
                          {{"inflow", fluid::BoundaryKind::supersonic_inflow, free_stream, {}},
                           {"outflow", fluid::BoundaryKind::supersonic_outflow, {}, {}},
                           {"walls", fluid::BoundaryKind::slip_wall, {}, {}},
                           {"symmetry", fluid::BoundaryKind::symmetry, {}, {}}});
  mpi::HaloExchange halo(comm, part);
  if (comm.size() > 1) model.set_distribution(mpi::flow_distribution(comm, halo, part));
  model.set_state([&](const Vec3& x) {
    const double pi = std::numbers::pi;
    fluid::Primitive s = free_stream;
    s.rho *= 1.0 + 0.2 * std::sin(2 * pi * x.x()) * std::sin(pi * x.y());
    s.pressure *= 1.0 + 0.3 * std::exp(-20 * (x - Vec3(0.5, 0.5, 0.5)).squaredNorm());
    return s;
  });
  model.step(model.stable_dt(0.5));  // touch every work array once
  comm.barrier();
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < steps; ++k) model.step(model.stable_dt(0.5));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double slowest = comm.max(seconds);
  const long most_cells = long(comm.max(double(local_cells)));
  if (comm.rank() == 0)
    std::printf(
        "%d rank(s) x %d thread(s): %ld tets, largest rank %ld cells (with its ghost layer), %.2f ms per step, "
        "%.2f M tet-updates/s (partition and local mesh %.2f s)\n",
        comm.size(), parallel::num_threads(), long(global.num_cells()), most_cells, 1e3 * slowest / steps,
        1e-6 * double(global.num_cells()) * steps / slowest, setup);
  return 0;
}
