// The flow on the ranks' parts of a mesh (FluidModel::set_distribution over HaloExchange)
// against the same flow in one model: a Mach 2 stream through a box carrying a pressure and
// density pulse, artificial viscosity on, 100 steps. Every rank's model takes the whole mesh's
// colouring restricted to its cells (fluid::restrict_colouring), so each owned node adds its
// element contributions in the one-model order: the owned nodes of every rank hold the
// one-model run's bits exactly (issue 21: bit-identical fields on any number of ranks).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "shellflow/fluid/fluid_model.h"
#include "shellflow/mesh/partition.h"
#include "shellflow/mpi/communicator.h"
#include "shellflow/mpi/flow_distribution.h"
#include "shellflow/mpi/halo_exchange.h"
#include "support/box_mesh.h"

namespace shellflow::mpi {
namespace {

using fluid::BoundaryCondition;
using fluid::BoundaryKind;
using fluid::Primitive;

constexpr double kLength = 1.2;

mesh::Mesh channel() {
  return support::box_mesh({12, 8, 4}, Vec3(kLength, 0.8, 0.4), [](const Vec3& c) {
    if (c.x() < 1e-9) return std::string("inflow");
    if (c.x() > kLength - 1e-9) return std::string("outflow");
    return std::string("walls");
  });
}

const Primitive stream{1.2, Vec3(680.0, 0.0, 0.0), 1.0e5};

Primitive pulse(const Vec3& x) {
  const double r2 = (x - Vec3(0.45, 0.4, 0.2)).squaredNorm();
  const double g = std::exp(-r2 / 0.02);
  return {stream.rho * (1.0 + 0.2 * g), stream.velocity + Vec3(0.0, 30.0 * g, 0.0), stream.pressure * (1.0 + 0.3 * g)};
}

fluid::FluidModel model(mesh::Mesh m, std::optional<fluid::CellColouring> colouring = std::nullopt) {
  fluid::FluidOptions o;
  o.q_dif = 1.0;
  std::vector<BoundaryCondition> bcs{{"inflow", BoundaryKind::supersonic_inflow, stream},
                                     {"outflow", BoundaryKind::supersonic_outflow},
                                     {"walls", BoundaryKind::slip_wall}};
  fluid::FluidModel f(std::move(m), o, std::move(bcs), std::move(colouring));
  f.set_state(pulse);
  return f;
}

TEST(DistributedFlow, OwnedNodesOfEveryRankFollowTheOneModelRunFor100Steps) {
  Communicator& comm = Communicator::world();
  const mesh::Mesh global = channel();
  const std::vector<int> cell_part = mesh::partition_cells(global, comm.size());
  const std::vector<int> owner = mesh::node_owners(global, cell_part);
  const mesh::LocalPart part = mesh::make_local_part(global, owner, comm.rank());

  fluid::FluidModel whole = model(global);
  const fluid::CellColouring whole_colouring = fluid::colour_cells(global.cells.connectivity, 4, global.num_nodes(),
                                                                   fluid::default_block_size(global.num_cells()));
  fluid::FluidModel mine =
      model(mesh::local_mesh(global, part), fluid::restrict_colouring(whole_colouring, part.cells));
  HaloExchange halo(comm, part);
  mine.set_distribution(flow_distribution(comm, halo, part));

  double largest_dt_difference = 0.0;
  for (int step = 0; step < 100; ++step) {
    const double dt_whole = whole.stable_dt(0.5);
    const double dt_mine = mine.stable_dt(0.5);
    largest_dt_difference = std::max(largest_dt_difference, std::abs(dt_mine / dt_whole - 1.0));
    whole.step(dt_whole);
    mine.step(dt_mine);
  }
  // The pulse has moved (the comparison is not of the initial state).
  const Index probe = Index(global.nodes.size() / 2);
  ASSERT_NE(whole.state().var[0][std::size_t(probe)], pulse(global.nodes[std::size_t(probe)]).rho);

  double worst = 0.0;
  for (int v = 0; v < fluid::num_variables; ++v) {
    const auto& g = whole.state().var[std::size_t(v)];
    double scale = 0.0;
    for (const double x : g) scale = std::max(scale, std::abs(x));
    for (Index i = 0; i < part.num_owned; ++i) {
      const double d =
          std::abs(mine.state().var[std::size_t(v)][std::size_t(i)] - g[std::size_t(part.nodes[std::size_t(i)])]);
      worst = std::max(worst, d / scale);
    }
  }
  const double worst_all = comm.max(worst);
  const double dt_all = comm.max(largest_dt_difference);
  if (comm.rank() == 0)
    std::printf("%d rank(s): largest relative difference to the one-model run after 100 steps %.3e (time step %.3e)\n",
                comm.size(), worst_all, dt_all);
  EXPECT_EQ(worst_all, 0.0);
  EXPECT_EQ(dt_all, 0.0);
  EXPECT_EQ(comm.sum(long(part.num_owned)), long(global.num_nodes()));
  EXPECT_NEAR(mine.time(), whole.time(), 1e-12 * whole.time());
}

}  // namespace
}  // namespace shellflow::mpi
