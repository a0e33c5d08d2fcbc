#include "shellflow/mpi/flow_distribution.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <type_traits>

#include "shellflow/core/error.h"

namespace shellflow::mpi {

fluid::FluidModel::Distribution flow_distribution(const Communicator& comm, HaloExchange& halo,
                                                  const mesh::LocalPart& part) {
  return {[&halo](std::span<double* const> fields) { halo.exchange(fields); },
          [&comm](double x) { return comm.min(x); }, [&comm](double x) { return comm.sum_in_rank_order(x); },
          [&comm](const std::string& message) { return comm.first_error(message); }, part.num_owned};
}

namespace {

/// The owned entries (`components` values per node) of every rank in whole node order, on
/// rank 0: each rank sends its owned nodes' whole indices and values.
std::vector<double> gather_whole(const Communicator& comm, const mesh::LocalPart& part, Index whole_nodes,
                                 int components, const double* local) {
  std::vector<double> mine;
  mine.reserve(std::size_t(part.num_owned) * std::size_t(components + 1));
  for (Index i = 0; i < part.num_owned; ++i) {
    mine.push_back(double(part.nodes[std::size_t(i)]));
    for (int c = 0; c < components; ++c)
      mine.push_back(local[std::size_t(i) * std::size_t(components) + std::size_t(c)]);
  }
  const std::vector<double> all = comm.gather(mine);
  if (comm.rank() != 0) return mine;  // not written (rank 0 writes)
  std::vector<double> whole(std::size_t(whole_nodes) * std::size_t(components), 0.0);
  const std::size_t stride = std::size_t(components) + 1;
  if (all.size() != std::size_t(whole_nodes) * stride)
    throw Error(fmt::format("distributed flow state: {} values gathered for {} nodes", all.size(), whole_nodes));
  for (std::size_t k = 0; k < all.size(); k += stride)
    std::copy_n(all.begin() + std::ptrdiff_t(k + 1), components,
                whole.begin() + std::ptrdiff_t(std::size_t(all[k]) * std::size_t(components)));
  return whole;
}

}  // namespace

void save_whole(const fluid::FluidModel& model, const Communicator& comm, const mesh::LocalPart& part,
                Index whole_nodes, ArchiveWriter& out) {
  const fluid::FluidSnapshot s = model.snapshot();
  for (const auto& v : s.U.var) out.put(gather_whole(comm, part, whole_nodes, 1, v.data()));
  for (const auto* field : {&s.x, &s.w}) {
    const std::vector<double> whole = gather_whole(comm, part, whole_nodes, 3, (*field)[0].data());
    std::vector<Vec3> vectors(whole.size() / 3);
    for (std::size_t a = 0; a < vectors.size(); ++a)
      vectors[a] = Vec3(whole[3 * a], whole[3 * a + 1], whole[3 * a + 2]);
    out.put(vectors);
  }
  out.put(s.time);
  out.put(s.steps);
  out.put(static_cast<std::uint64_t>(s.wall_velocity.size()));
  const auto& conditions = model.boundaries().conditions();
  for (std::size_t c = 0; c < s.wall_velocity.size(); ++c) {
    // Set per node of the condition's group (sorted whole nodes in the whole mesh): the owned
    // ones gathered with their whole node, put in whole node order.
    const auto& local = s.wall_velocity[c];
    const std::vector<Index>& group = model.mesh().group(conditions[c].group).nodes;
    const bool set = comm.any(!local.empty());
    std::vector<double> mine;
    for (std::size_t j = 0; set && j < local.size(); ++j)
      if (group[j] < part.num_owned)
        mine.insert(mine.end(), {double(part.nodes[std::size_t(group[j])]), local[j].x(), local[j].y(), local[j].z()});
    std::vector<double> all = set ? comm.gather(mine) : std::vector<double>{};
    std::vector<std::array<double, 4>> rows(all.size() / 4);
    for (std::size_t k = 0; k < rows.size(); ++k) std::copy_n(all.begin() + std::ptrdiff_t(4 * k), 4, rows[k].begin());
    std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a[0] < b[0]; });
    std::vector<Vec3> whole(rows.size());
    for (std::size_t k = 0; k < rows.size(); ++k) whole[k] = Vec3(rows[k][1], rows[k][2], rows[k][3]);
    out.put(whole);
  }
  out.put(s.density_rate);
}

void restore_whole(fluid::FluidModel& model, const Communicator& comm, const mesh::LocalPart& part, Index whole_nodes,
                   ArchiveReader& in) {
  fluid::FluidSnapshot s;
  const auto nn = std::size_t(whole_nodes);
  const auto local = [&](const auto& whole) {
    std::remove_cvref_t<decltype(whole)> out(part.nodes.size());
    for (std::size_t i = 0; i < part.nodes.size(); ++i) out[i] = whole[std::size_t(part.nodes[i])];
    return out;
  };
  for (auto& v : s.U.var) {
    const auto whole = in.get_vector<double>();
    in.expect_size("the flow's state", whole.size(), nn);
    v = local(whole);
  }
  for (auto* field : {&s.x, &s.w}) {
    const auto whole = in.get_vec3s();
    in.expect_size("the fluid node positions and velocities", whole.size(), nn);
    *field = local(whole);
  }
  s.time = in.get<double>();
  s.steps = in.get<long>();
  const auto walls = in.get<std::uint64_t>();
  const auto& conditions = model.boundaries().conditions();
  in.expect_size("the flow's wall conditions", walls, conditions.size());
  for (std::uint64_t c = 0; c < walls; ++c) {
    const std::vector<Vec3> whole = in.get_vec3s();
    s.wall_velocity.emplace_back();
    if (whole.empty()) continue;
    // The whole group's nodes: every rank's owned nodes of it, sorted (whole node order).
    const std::vector<Index>& group = model.mesh().group(conditions[c].group).nodes;
    std::vector<double> mine;
    for (const Index l : group)
      if (l < part.num_owned) mine.push_back(double(part.nodes[std::size_t(l)]));
    std::vector<double> ids = comm.all_gather(mine);
    std::sort(ids.begin(), ids.end());
    in.expect_size("the wall velocities of '" + conditions[c].group + "'", whole.size(), ids.size());
    for (const Index l : group) {
      const double id = double(part.nodes[std::size_t(l)]);
      s.wall_velocity.back().push_back(whole[std::size_t(std::lower_bound(ids.begin(), ids.end(), id) - ids.begin())]);
    }
  }
  s.density_rate = in.get<double>();
  model.restore(s);
}

}  // namespace shellflow::mpi
