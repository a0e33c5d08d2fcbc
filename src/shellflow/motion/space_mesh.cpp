#include "shellflow/motion/space_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "shellflow/core/error.h"
#include "shellflow/core/parallel.h"
#include "shellflow/fem/quadrature.h"
#include "shellflow/fem/reference_element.h"
#include "shellflow/fem/shape_functions.h"
#include "shellflow/mesh/quality.h"
#include "shellflow/mesh/spatial_index.h"

namespace shellflow::motion {
namespace {

using fem::Tet20;
constexpr int kNodes = Tet20::num_nodes;

/// Per-step loops with less work than this (multiply-adds) run on one thread: starting the
/// team costs more than it saves (and much more on a loaded machine).
constexpr std::ptrdiff_t parallel_work_threshold = 100000;

/// Nodes of element e, gathered.
std::array<Vec3, kNodes> element_nodes(const mesh::Mesh& m, std::span<const Vec3> x, Index e) {
  std::array<Vec3, kNodes> X;
  const auto nodes = m.cells.element(e);
  for (int a = 0; a < kNodes; ++a)
    X[static_cast<std::size_t>(a)] = x[static_cast<std::size_t>(nodes[static_cast<std::size_t>(a)])];
  return X;
}

Vec3 map_point(const std::array<Vec3, kNodes>& X, const double* xi) {
  double N[kNodes];
  Tet20::eval(xi, N);
  Vec3 x = Vec3::Zero();
  for (int a = 0; a < kNodes; ++a) x += N[a] * X[static_cast<std::size_t>(a)];
  return x;
}

Mat3 map_jacobian(const std::array<Vec3, kNodes>& X, const double* xi) {
  double dN[kNodes * 3];
  Tet20::eval_gradients(xi, dN);
  Mat3 J = Mat3::Zero();
  for (int a = 0; a < kNodes; ++a)
    J += X[static_cast<std::size_t>(a)] * Eigen::RowVector3d(dN[3 * a], dN[3 * a + 1], dN[3 * a + 2]);
  return J;
}

/// Euclidean projection of xi onto the reference tetrahedron (simplex projection on the
/// three coordinates plus the slack 1 - sum).
Vec3 project_to_reference(const Vec3& xi) {
  // Project (xi1, xi2, xi3, 1 - sum) onto the probability simplex (Duchi et al.).
  std::array<double, 4> v{xi[0], xi[1], xi[2], 1.0 - xi.sum()};
  std::array<double, 4> u = v;
  std::sort(u.begin(), u.end(), std::greater<>());
  double cumulative = 0.0, theta = 0.0;
  for (int i = 0; i < 4; ++i) {
    cumulative += u[static_cast<std::size_t>(i)];
    const double t = (cumulative - 1.0) / (i + 1);
    if (u[static_cast<std::size_t>(i)] - t > 0.0) theta = t;
  }
  return Vec3(std::max(v[0] - theta, 0.0), std::max(v[1] - theta, 0.0), std::max(v[2] - theta, 0.0));
}

struct NewtonResult {
  Vec3 xi;
  double residual;
  int iterations;
};

/// Newton on x(xi) = P from the straight-sided tetrahedron's xi.
NewtonResult newton_locate(const std::array<Vec3, kNodes>& X, const Vec3& P, double tolerance) {
  Mat3 J0;
  for (int k = 0; k < 3; ++k) J0.col(k) = X[static_cast<std::size_t>(k + 1)] - X[0];
  Vec3 xi = J0.partialPivLu().solve(P - X[0]);
  Vec3 r = map_point(X, xi.data()) - P;
  int it = 0;
  for (; it < 30 && r.norm() > tolerance; ++it) {
    const Mat3 J = map_jacobian(X, xi.data());
    xi -= J.partialPivLu().solve(r);
    r = map_point(X, xi.data()) - P;
  }
  return {xi, r.norm(), it};
}

double outside_measure(const Vec3& xi) { return std::max(-xi.minCoeff(), xi.sum() - 1.0); }

Vec3 facet_normal(std::span<const Vec3> x, std::span<const Index> facet) {
  const Vec3& a = x[static_cast<std::size_t>(facet[0])];
  return (x[static_cast<std::size_t>(facet[1])] - a).cross(x[static_cast<std::size_t>(facet[2])] - a).normalized();
}

}  // namespace

std::vector<double> lumped_node_areas(std::span<const Vec3> nodes, const mesh::ElementBlock& facets) {
  std::vector<double> area(nodes.size(), 0.0);
  const auto& rule = fem::triangle_rule(6);
  fem::visit_element_type(static_cast<int>(facets.type), [&](auto element) {
    using E = decltype(element);
    if constexpr (E::dim == 2) {
      for (Index f = 0; f < facets.size(); ++f) {
        const auto v = facets.element(f);
        for (int q = 0; q < rule.size(); ++q) {
          double N[E::num_nodes], dN[E::num_nodes * 2];
          E::eval(rule.point(q).data(), N);
          E::eval_gradients(rule.point(q).data(), dN);
          Vec3 t1 = Vec3::Zero(), t2 = Vec3::Zero();
          for (int a = 0; a < E::num_nodes; ++a) {
            t1 += dN[2 * a] * nodes[static_cast<std::size_t>(v[static_cast<std::size_t>(a)])];
            t2 += dN[2 * a + 1] * nodes[static_cast<std::size_t>(v[static_cast<std::size_t>(a)])];
          }
          const double dA = t1.cross(t2).norm() * rule.weights[static_cast<std::size_t>(q)];
          for (int a = 0; a < E::num_nodes; ++a)
            area[static_cast<std::size_t>(v[static_cast<std::size_t>(a)])] += N[a] * dA;
        }
      }
    } else {
      throw Error("lumped_node_areas: the facets are not triangles");
    }
  });
  return area;
}

NodeClassification classify_nodes(const mesh::Mesh& m, const std::vector<std::string>& interface_groups,
                                  const std::vector<std::string>& fixed_groups,
                                  const std::vector<std::string>& sliding_groups) {
  const auto n = static_cast<std::size_t>(m.num_nodes());
  NodeClassification c{std::vector<NodeClass>(n, NodeClass::interior),
                       std::vector<std::array<Vec3, 2>>(n, {Vec3::Zero(), Vec3::Zero()})};
  // Classes in reverse precedence, so that the stronger class overwrites.
  for (const auto& name : sliding_groups) {
    const auto& group = m.group(name);
    for (Index f = 0; f < group.elements.size(); ++f) {
      const auto facet = group.elements.element(f);
      const Vec3 normal = facet_normal(m.nodes, facet);
      for (Index node : facet) {
        auto& normals = c.sliding_normals[static_cast<std::size_t>(node)];
        c.classes[static_cast<std::size_t>(node)] = NodeClass::sliding;
        if (std::abs(normals[0].dot(normal)) > 1.0 - 1e-8 || std::abs(normals[1].dot(normal)) > 1.0 - 1e-8) continue;
        if (normals[0].isZero()) {
          normals[0] = normal;
        } else if (normals[1].isZero()) {
          normals[1] = (normal - normal.dot(normals[0]) * normals[0]).normalized();
        } else {
          throw_input_error(
              "{}: sliding group '{}' is not planar near node {} (tag {}); sliding "
              "(symmetry) groups must be planes",
              m.source, name, node, m.node_tags[static_cast<std::size_t>(node)]);
        }
      }
    }
  }
  for (const auto& name : fixed_groups)
    for (Index node : m.group(name).nodes) c.classes[static_cast<std::size_t>(node)] = NodeClass::fixed;
  for (const auto& name : interface_groups)
    for (Index node : m.group(name).nodes) c.classes[static_cast<std::size_t>(node)] = NodeClass::interface;
  return c;
}

SpaceMesh::SpaceMesh(const mesh::Mesh& space, SpaceMeshOptions options) : mesh_(space), options_(std::move(options)) {
  if (mesh_.cells.type != mesh::ElementType::tet20) {
    throw_input_error(
        "{}: the space mesh must be made of 20-node (cubic) tetrahedra, it holds "
        "{}s; mesh it with order 3",
        mesh_.source, mesh::element_info(mesh_.cells.type).name);
  }
  const auto n = static_cast<std::size_t>(mesh_.num_nodes());
  auto classification =
      classify_nodes(mesh_, options_.interface_groups, options_.fixed_groups, options_.sliding_groups);
  classes_ = std::move(classification.classes);
  sliding_normals_ = std::move(classification.sliding_normals);

  // Fixed-boundary areas, for area weighting.
  fixed_areas_.assign(n, 0.0);
  for (const auto& name : options_.fixed_groups) {
    const auto areas = lumped_node_areas(mesh_.nodes, mesh_.group(name).elements);
    for (std::size_t i = 0; i < n; ++i) fixed_areas_[i] += areas[i];
  }

  for (Index i = 0; i < mesh_.num_nodes(); ++i) {
    switch (classes_[static_cast<std::size_t>(i)]) {
      case NodeClass::interface:
        interface_nodes_.push_back(i);
        break;
      case NodeClass::fixed:
        fixed_nodes_.push_back(i);
        break;
      case NodeClass::sliding:
      case NodeClass::interior:
        idw_nodes_.push_back(i);
        break;
    }
  }

  reference_jacobian_.resize(static_cast<std::size_t>(mesh_.num_cells()));
  for (Index e = 0; e < mesh_.num_cells(); ++e) {
    const auto v = mesh_.cells.element(e);
    const double volume = mesh::tet_signed_volume(
        mesh_.nodes[static_cast<std::size_t>(v[0])], mesh_.nodes[static_cast<std::size_t>(v[1])],
        mesh_.nodes[static_cast<std::size_t>(v[2])], mesh_.nodes[static_cast<std::size_t>(v[3])]);
    if (!(volume > 0.0)) {
      throw_input_error("{}: space-mesh element {} is inverted (volume {:.3g} m^3); fix the mesh", mesh_.source, e,
                        volume);
    }
    reference_jacobian_[static_cast<std::size_t>(e)] = 6.0 * volume;
  }
  displacement_.assign(n, Vec3::Zero());
  velocity_.assign(n, Vec3::Zero());
}

void SpaceMesh::set_interface_samples(std::span<const Vec3> samples, std::span<const double> interface_areas) {
  const bool by_area = options_.weighting == IdwWeighting::area;
  if (by_area && interface_areas.size() != samples.size()) {
    throw Error(
        fmt::format("space mesh: {} interface areas given for {} samples", interface_areas.size(), samples.size()));
  }
  if (samples.empty()) throw Error("space mesh: no interface samples");
  num_samples_ = static_cast<Index>(samples.size());
  const std::size_t rows = idw_nodes_.size();
  sample_weights_.assign(rows * samples.size(), 0.0);
  fixed_weights_.assign(rows * fixed_nodes_.size(), 0.0);
  const double e1 = options_.interface_exponent, e2 = options_.fixed_exponent;

#pragma omp parallel for schedule(static)
  for (std::size_t r = 0; r < rows; ++r) {
    const Vec3& X = mesh_.nodes[static_cast<std::size_t>(idw_nodes_[r])];
    double* a = sample_weights_.data() + r * samples.size();
    double* b = fixed_weights_.data() + r * fixed_nodes_.size();
    double sum = 0.0;
    for (std::size_t j = 0; j < samples.size(); ++j) {
      // A node on a sample (d = 0) would give inf/inf: weight 1 to that sample instead.
      const double d = (X - samples[j]).norm();
      a[j] = d > 0.0 ? (by_area ? interface_areas[j] : 1.0) / std::pow(d, e1) : std::numeric_limits<double>::max();
      sum += a[j];
    }
    for (std::size_t l = 0; l < fixed_nodes_.size(); ++l) {
      const auto node = static_cast<std::size_t>(fixed_nodes_[l]);
      b[l] = (by_area ? fixed_areas_[node] : 1.0) / std::pow((X - mesh_.nodes[node]).norm(), e2);
      sum += b[l];
    }
    if (!std::isfinite(sum)) {  // a coincident sample dominates
      for (std::size_t j = 0; j < samples.size(); ++j) a[j] = a[j] == std::numeric_limits<double>::max();
      std::fill(b, b + fixed_nodes_.size(), 0.0);
      continue;
    }
    for (std::size_t j = 0; j < samples.size(); ++j) a[j] /= sum;
    for (std::size_t l = 0; l < fixed_nodes_.size(); ++l) b[l] /= sum;
  }
}

LocationReport SpaceMesh::locate(std::span<const Vec3> fluid_nodes) {
  LocationReport report;
  const mesh::BoxTree tree(mesh::element_boxes(mesh_.nodes, mesh_.cells, 0.05));
  std::vector<double> size(static_cast<std::size_t>(mesh_.num_cells()));
  for (Index e = 0; e < mesh_.num_cells(); ++e) size[static_cast<std::size_t>(e)] = tree.box(e).extent().norm() / 1.1;
  locations_.assign(fluid_nodes.size(), NodeLocation{});
  fluid_initial_.assign(fluid_nodes.begin(), fluid_nodes.end());
  const double tol = options_.location_tolerance;

  for (std::size_t p = 0; p < fluid_nodes.size(); ++p) {
    const Vec3& P = fluid_nodes[p];
    Index best = -1;
    NewtonResult best_result{Vec3::Zero(), std::numeric_limits<double>::infinity(), 0};
    double best_outside = std::numeric_limits<double>::infinity();
    bool inside = false;
    tree.for_each_containing(P, [&](Index e) {
      const auto X = element_nodes(mesh_, mesh_.nodes, e);
      const auto result = newton_locate(X, P, 1e-12 * size[static_cast<std::size_t>(e)]);
      const double outside = outside_measure(result.xi);
      if (result.residual < 1e-10 * size[static_cast<std::size_t>(e)] && outside < best_outside) {
        best = e;
        best_result = result;
        best_outside = outside;
      }
      inside = best_outside <= tol;
      return !inside;
    });
    if (!inside) {
      // Outside every element (within the tolerance): attach to the element whose map
      // comes closest, with xi projected into the reference tetrahedron.
      const auto hit = tree.nearest(P, [&](Index e) {
        const auto X = element_nodes(mesh_, mesh_.nodes, e);
        const Vec3 xi = project_to_reference(newton_locate(X, P, 1e-12 * size[static_cast<std::size_t>(e)]).xi);
        return (map_point(X, xi.data()) - P).norm();
      });
      if (hit.index < 0 || hit.distance > options_.max_relative_gap * size[static_cast<std::size_t>(hit.index)]) {
        throw_input_error(
            "{}: fluid node {} at ({:.6g}, {:.6g}, {:.6g}) lies outside the space mesh (gap {:.3g} "
            "m to element {}); the space mesh must cover the fluid domain: mesh both from the "
            "same geometry",
            mesh_.source, p, P.x(), P.y(), P.z(), hit.distance, hit.index);
      }
      const auto X = element_nodes(mesh_, mesh_.nodes, hit.index);
      best = hit.index;
      best_result.xi = project_to_reference(newton_locate(X, P, 1e-12 * size[static_cast<std::size_t>(best)]).xi);
      ++report.projected;
      report.max_gap = std::max(report.max_gap, hit.distance);
    } else {
      ++report.located;
      report.max_residual = std::max(report.max_residual, best_result.residual);
      report.max_newton_iterations = std::max(report.max_newton_iterations, best_result.iterations);
    }
    auto& location = locations_[p];
    location.element = best;
    Tet20::eval(best_result.xi.data(), location.shape.data());
  }
  return report;
}

void SpaceMesh::move(std::span<const Vec3> interface_u, std::span<const Vec3> interface_v,
                     std::span<const Vec3> sample_u, std::span<const Vec3> sample_v, std::span<const Vec3> fixed_u) {
  if (interface_u.size() != interface_nodes_.size() || interface_v.size() != interface_nodes_.size()) {
    throw Error(fmt::format("space mesh: {} interface displacements for {} interface nodes", interface_u.size(),
                            interface_nodes_.size()));
  }
  if (static_cast<Index>(sample_u.size()) != num_samples_ || sample_v.size() != sample_u.size()) {
    throw Error(
        fmt::format("space mesh: {} sample displacements for {} samples (call "
                    "set_interface_samples first)",
                    sample_u.size(), num_samples_));
  }
  for (std::size_t i = 0; i < interface_nodes_.size(); ++i) {
    displacement_[static_cast<std::size_t>(interface_nodes_[i])] = interface_u[i];
    velocity_[static_cast<std::size_t>(interface_nodes_[i])] = interface_v[i];
  }
  for (std::size_t l = 0; l < fixed_nodes_.size(); ++l) {
    displacement_[static_cast<std::size_t>(fixed_nodes_[l])] = fixed_u.empty() ? Vec3::Zero() : fixed_u[l];
    velocity_[static_cast<std::size_t>(fixed_nodes_[l])] = Vec3::Zero();
  }
  const std::size_t ns = sample_u.size(), nf = fixed_nodes_.size();
  const auto rows = static_cast<std::ptrdiff_t>(idw_nodes_.size());
  parallel::for_range(
      Index(rows),
      parallel::grain_if(rows * std::ptrdiff_t(2 * ns + nf) > parallel_work_threshold,
                         Index(std::max<std::ptrdiff_t>(1, parallel_work_threshold / std::ptrdiff_t(2 * ns + nf + 1))),
                         Index(rows)),
      [&](Index begin, Index end) {
        for (Index row = begin; row < end; ++row) {
          const auto r = static_cast<std::size_t>(row);
          const double* a = sample_weights_.data() + r * ns;
          Vec3 u = Vec3::Zero(), v = Vec3::Zero();
          for (std::size_t j = 0; j < ns; ++j) {
            u += a[j] * sample_u[j];
            v += a[j] * sample_v[j];
          }
          if (!fixed_u.empty()) {
            const double* b = fixed_weights_.data() + r * nf;
            for (std::size_t l = 0; l < nf; ++l) u += b[l] * fixed_u[l];
          }
          const auto node = static_cast<std::size_t>(idw_nodes_[r]);
          if (classes_[node] == NodeClass::sliding) {
            u = project_on_sliding_planes(u, sliding_normals_[node]);
            v = project_on_sliding_planes(v, sliding_normals_[node]);
          }
          displacement_[node] = u;
          velocity_[node] = v;
        }
      });
}

void SpaceMesh::set_node_motion(std::span<const Vec3> u, std::span<const Vec3> v) {
  if (u.size() != displacement_.size() || v.size() != velocity_.size()) {
    throw Error(fmt::format("space mesh: {} node displacements for {} nodes", u.size(), displacement_.size()));
  }
  std::copy(u.begin(), u.end(), displacement_.begin());
  std::copy(v.begin(), v.end(), velocity_.begin());
}

namespace {

/// x = X + sum_k N_k u_k (initial empty: x = sum_k N_k u_k) and, with R = 6,
/// w = sum_k N_k v_k, from records of R doubles per space-mesh node ((u) or (u, v)).
template <int R>
void interpolate_records(const double* records, const Index* connectivity, std::span<const NodeLocation> locations,
                         std::span<const Vec3> initial, std::span<Vec3> fluid_x, std::span<Vec3> fluid_w) {
  const auto n = static_cast<std::ptrdiff_t>(locations.size());
  parallel::for_range(Index(n),
                      parallel::grain_if(n * kNodes * R > parallel_work_threshold,
                                         Index(parallel_work_threshold / (kNodes * R)), Index(n)),
                      [&](Index begin, Index end) {
                        for (Index p = begin; p < end; ++p) {
                          const NodeLocation& loc = locations[static_cast<std::size_t>(p)];
                          const Index* nodes = connectivity + static_cast<std::ptrdiff_t>(loc.element) * kNodes;
                          double acc[R] = {};
                          for (int a = 0; a < kNodes; ++a) {
                            const double* r = records + R * static_cast<std::ptrdiff_t>(nodes[a]);
                            const double N = loc.shape[static_cast<std::size_t>(a)];
                            for (int i = 0; i < R; ++i) acc[i] += N * r[i];
                          }
                          if (initial.empty()) {
                            fluid_x[static_cast<std::size_t>(p)] = Vec3(acc[0], acc[1], acc[2]);
                          } else {
                            const Vec3& X = initial[static_cast<std::size_t>(p)];
                            fluid_x[static_cast<std::size_t>(p)] = Vec3(X[0] + acc[0], X[1] + acc[1], X[2] + acc[2]);
                          }
                          if constexpr (R == 6) fluid_w[static_cast<std::size_t>(p)] = Vec3(acc[3], acc[4], acc[5]);
                        }
                      });
}

}  // namespace

void SpaceMesh::interpolate(std::span<Vec3> fluid_x, std::span<Vec3> fluid_w) const {
  // x = X + sum_k N_k u_k rather than the paper's sum_k N_k x_k (eq. 31): equal in exact
  // arithmetic, but this way an unmoved mesh returns every fluid node at exactly its
  // initial position (also a node projected from just outside), and a uniform translation
  // moves every node by exactly that translation.
  //
  // The space mesh is small (~1 000 nodes): pack u (and v) of each of its nodes into one
  // record first, so the per-fluid-node loop gathers 20 contiguous records and runs 3 (6)
  // independent multiply-add chains. fluid_w empty: positions only.
  const bool velocities = !fluid_w.empty();
  const int r = velocities ? 6 : 3;
  motion_records_.resize(std::size_t(r) * displacement_.size());
  for (std::size_t k = 0; k < displacement_.size(); ++k) {
    double* rec = motion_records_.data() + std::size_t(r) * k;
    for (int i = 0; i < 3; ++i) {
      rec[i] = displacement_[k][i];
      if (velocities) rec[3 + i] = velocity_[k][i];
    }
  }
  const Index* connectivity = mesh_.cells.connectivity.data();
  if (velocities)
    interpolate_records<6>(motion_records_.data(), connectivity, locations_, fluid_initial_, fluid_x, fluid_w);
  else
    interpolate_records<3>(motion_records_.data(), connectivity, locations_, fluid_initial_, fluid_x, fluid_w);
}

void SpaceMesh::interpolate_displacement(std::span<Vec3> fluid_u) const {
  motion_records_.resize(3 * displacement_.size());
  for (std::size_t k = 0; k < displacement_.size(); ++k)
    for (int i = 0; i < 3; ++i) motion_records_[3 * k + std::size_t(i)] = displacement_[k][i];
  interpolate_records<3>(motion_records_.data(), mesh_.cells.connectivity.data(), locations_, {}, fluid_u, {});
}

std::vector<Vec3> SpaceMesh::current_positions() const {
  std::vector<Vec3> x(mesh_.nodes.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = mesh_.nodes[i] + displacement_[i];
  return x;
}

namespace {
/// Points where the cubic map's Jacobian is checked: the 20 nodes and a degree-4 rule.
const std::vector<Vec3>& jacobian_check_points() {
  static const std::vector<Vec3> points = [] {
    std::vector<Vec3> p;
    for (const auto& node : Tet20::nodes()) p.emplace_back(node[0], node[1], node[2]);
    const auto& rule = fem::tetrahedron_rule(4);
    for (int q = 0; q < rule.size(); ++q) p.emplace_back(rule.point(q)[0], rule.point(q)[1], rule.point(q)[2]);
    return p;
  }();
  return points;
}

std::pair<double, Index> min_jacobian(const mesh::Mesh& m, std::span<const Vec3> x, std::span<const double> reference) {
  double worst = std::numeric_limits<double>::infinity();
  Index worst_element = -1;
  for (Index e = 0; e < m.num_cells(); ++e) {
    const auto X = element_nodes(m, x, e);
    for (const Vec3& xi : jacobian_check_points()) {
      const double j = map_jacobian(X, xi.data()).determinant() / reference[static_cast<std::size_t>(e)];
      if (std::isnan(j)) return {j, e};  // NaN positions: the worst there is
      if (j < worst) {
        worst = j;
        worst_element = e;
      }
    }
  }
  return {worst, worst_element};
}
}  // namespace

double SpaceMesh::min_relative_jacobian() const {
  return min_jacobian(mesh_, current_positions(), reference_jacobian_).first;
}

}  // namespace shellflow::motion
