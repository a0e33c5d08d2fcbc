#include "shellflow/mpi/flow_distribution.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>

#include "shellflow/core/error.h"
#include "shellflow/fluid/snapshot_io.h"

namespace shellflow::mpi {

fluid::FluidModel::Distribution flow_distribution(const Communicator& comm, HaloExchange& halo,
                                                  const mesh::LocalPart& part) {
  return {[&halo](std::span<double* const> fields) { halo.exchange(fields); },
          [&comm](double x) { return comm.min(x); }, [&comm](double x) { return comm.sum_in_rank_order(x); },
          [&comm](const std::string& message) { return comm.first_error(message); }, part.num_owned};
}

namespace {

/// The snapshot layout of a rank's part: the owners' values gathered to rank 0 in whole node
/// order (the other ranks return their own: they write nothing), the whole taken apart on
/// every rank.
class OwnersLayout final : public fluid::SnapshotLayout {
 public:
  OwnersLayout(const Communicator& comm, const mesh::LocalPart& part, Index whole_nodes)
      : comm_(comm), part_(part), whole_(std::size_t(whole_nodes)) {}

  std::vector<double> gather(std::span<const double> local, int components) const override {
    const auto nc = std::size_t(components);
    std::vector<double> mine;  // per owned node: its whole index, then its values
    mine.reserve(std::size_t(part_.num_owned) * (nc + 1));
    for (Index i = 0; i < part_.num_owned; ++i) {
      mine.push_back(double(part_.nodes[std::size_t(i)]));
      for (std::size_t c = 0; c < nc; ++c) mine.push_back(local[std::size_t(i) * nc + c]);
    }
    const std::vector<double> all = comm_.gather(mine);
    if (comm_.rank() != 0) return mine;  // not written (rank 0 writes)
    std::vector<double> whole(whole_ * nc, 0.0);
    const std::size_t stride = nc + 1;
    if (all.size() != whole_ * stride)
      throw Error(fmt::format("distributed flow state: {} values gathered for {} nodes", all.size(), whole_));
    for (std::size_t k = 0; k < all.size(); k += stride)
      std::copy_n(all.begin() + std::ptrdiff_t(k + 1), nc, whole.begin() + std::ptrdiff_t(std::size_t(all[k]) * nc));
    return whole;
  }

  std::vector<Vec3> gather_group(std::span<const Index> group, std::span<const Vec3> local) const override {
    // The owned nodes' values with their whole node, put in whole node order.
    const bool set = comm_.any(!local.empty());
    if (!set) return {};
    std::vector<double> mine;
    for (std::size_t j = 0; j < local.size(); ++j)
      if (group[j] < part_.num_owned)
        mine.insert(mine.end(), {double(part_.nodes[std::size_t(group[j])]), local[j].x(), local[j].y(), local[j].z()});
    const std::vector<double> all = comm_.gather(mine);
    std::vector<std::array<double, 4>> rows(all.size() / 4);
    for (std::size_t k = 0; k < rows.size(); ++k) std::copy_n(all.begin() + std::ptrdiff_t(4 * k), 4, rows[k].begin());
    std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a[0] < b[0]; });
    std::vector<Vec3> whole(rows.size());
    for (std::size_t k = 0; k < rows.size(); ++k) whole[k] = Vec3(rows[k][1], rows[k][2], rows[k][3]);
    return whole;
  }

  std::size_t whole_nodes() const override { return whole_; }

  std::vector<double> scatter(std::span<const double> whole, int components) const override {
    const auto nc = std::size_t(components);
    std::vector<double> out(part_.nodes.size() * nc);
    for (std::size_t i = 0; i < part_.nodes.size(); ++i)
      std::copy_n(whole.begin() + std::ptrdiff_t(std::size_t(part_.nodes[i]) * nc), nc,
                  out.begin() + std::ptrdiff_t(i * nc));
    return out;
  }

  std::vector<Vec3> scatter_group(std::span<const Index> group, std::span<const Vec3> whole, ArchiveReader& in,
                                  const std::string& what) const override {
    // The whole group's nodes: every rank's owned nodes of it, sorted (whole node order).
    std::vector<double> mine;
    for (const Index l : group)
      if (l < part_.num_owned) mine.push_back(double(part_.nodes[std::size_t(l)]));
    std::vector<double> ids = comm_.all_gather(mine);
    std::sort(ids.begin(), ids.end());
    in.expect_size(what, whole.size(), ids.size());
    std::vector<Vec3> out;
    for (const Index l : group) {
      const double id = double(part_.nodes[std::size_t(l)]);
      out.push_back(whole[std::size_t(std::lower_bound(ids.begin(), ids.end(), id) - ids.begin())]);
    }
    return out;
  }

 private:
  const Communicator& comm_;
  const mesh::LocalPart& part_;
  std::size_t whole_;
};

}  // namespace

void save_whole(const fluid::FluidModel& model, const Communicator& comm, const mesh::LocalPart& part,
                Index whole_nodes, ArchiveWriter& out) {
  const OwnersLayout layout(comm, part, whole_nodes);
  fluid::write_snapshot(model, out, &layout);
}

void restore_whole(fluid::FluidModel& model, const Communicator& comm, const mesh::LocalPart& part, Index whole_nodes,
                   ArchiveReader& in) {
  const OwnersLayout layout(comm, part, whole_nodes);
  fluid::read_snapshot(model, in, &layout);
}

}  // namespace shellflow::mpi
