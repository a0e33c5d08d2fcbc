#include "shellflow/fluid/snapshot_io.h"

namespace shellflow::fluid {
namespace {

std::span<const double> flat(const std::vector<Vec3>& v) { return {v.empty() ? nullptr : v[0].data(), 3 * v.size()}; }

std::vector<Vec3> vectors(const std::vector<double>& flat) {
  std::vector<Vec3> v(flat.size() / 3);
  for (std::size_t a = 0; a < v.size(); ++a) v[a] = Vec3(flat[3 * a], flat[3 * a + 1], flat[3 * a + 2]);
  return v;
}

}  // namespace

void write_snapshot(const FluidModel& model, ArchiveWriter& out, const SnapshotLayout* layout) {
  const FluidSnapshot s = model.snapshot();
  for (const auto& v : s.U.var)
    if (layout)
      out.put(layout->gather(v, 1));
    else
      out.put(v);
  for (const auto* field : {&s.x, &s.w})
    if (layout)
      out.put(vectors(layout->gather(flat(*field), 3)));
    else
      out.put(*field);
  out.put(s.time);
  out.put(s.steps);
  out.put(static_cast<std::uint64_t>(s.wall_velocity.size()));
  const auto& conditions = model.boundaries().conditions();
  for (std::size_t c = 0; c < s.wall_velocity.size(); ++c)
    if (layout)
      out.put(layout->gather_group(model.mesh().group(conditions[c].group).nodes, s.wall_velocity[c]));
    else
      out.put(s.wall_velocity[c]);
  out.put(s.density_rate);
}

void read_snapshot(FluidModel& model, ArchiveReader& in, const SnapshotLayout* layout) {
  FluidSnapshot s;
  const std::size_t whole = layout ? layout->whole_nodes() : std::size_t(model.mesh().num_nodes());
  for (auto& v : s.U.var) {
    v = in.get_vector<double>();
    in.expect_size("the flow's state", v.size(), whole);
    if (layout) v = layout->scatter(v, 1);
  }
  for (auto* field : {&s.x, &s.w}) {
    *field = in.get_vec3s();
    in.expect_size(field == &s.x ? "the fluid node positions" : "the fluid mesh velocities", field->size(), whole);
    if (layout) *field = vectors(layout->scatter(flat(*field), 3));
  }
  s.time = in.get<double>();
  s.steps = in.get<long>();
  const auto walls = in.get<std::uint64_t>();
  const auto& conditions = model.boundaries().conditions();
  in.expect_size("the flow's wall conditions", walls, conditions.size());
  for (std::uint64_t c = 0; c < walls; ++c) {
    std::vector<Vec3> v = in.get_vec3s();
    if (layout && !v.empty())
      v = layout->scatter_group(model.mesh().group(conditions[c].group).nodes, v, in,
                                "the wall velocities of '" + conditions[c].group + "'");
    s.wall_velocity.push_back(std::move(v));
  }
  s.density_rate = in.get<double>();
  model.restore(s);
}

}  // namespace shellflow::fluid
