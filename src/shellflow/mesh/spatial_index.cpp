#include "shellflow/mesh/spatial_index.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nanoflann.hpp>
#include <numeric>
#include <queue>

#include "shellflow/core/error.h"

namespace shellflow::mesh {

// ---------------------------------------------------------------- PointIndex

struct PointIndex::Impl {
  struct Cloud {
    std::vector<Vec3> points;
    std::size_t kdtree_get_point_count() const { return points.size(); }
    double kdtree_get_pt(std::size_t i, std::size_t d) const { return points[i][static_cast<Index>(d)]; }
    template <class Bbox>
    bool kdtree_get_bbox(Bbox&) const {
      return false;
    }
  };
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3, Index>;
  Cloud cloud;
  Tree tree;
  explicit Impl(std::vector<Vec3> points)
      : cloud{std::move(points)}, tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {}
};

PointIndex::PointIndex(std::vector<Vec3> points) {
  if (points.empty()) throw Error("PointIndex: no points to index");
  impl_ = std::make_unique<Impl>(std::move(points));
}
PointIndex::~PointIndex() = default;
PointIndex::PointIndex(PointIndex&&) noexcept = default;
PointIndex& PointIndex::operator=(PointIndex&&) noexcept = default;

Index PointIndex::size() const { return static_cast<Index>(impl_->cloud.points.size()); }

PointHit PointIndex::nearest(const Vec3& p) const { return nearest(p, 1).front(); }

std::vector<PointHit> PointIndex::nearest(const Vec3& p, int k) const {
  const auto n = static_cast<std::size_t>(std::clamp<Index>(k, 1, size()));
  std::vector<Index> indices(n);
  std::vector<double> d2(n);
  const auto found = impl_->tree.knnSearch(p.data(), n, indices.data(), d2.data());
  std::vector<PointHit> hits(found);
  for (std::size_t i = 0; i < found; ++i) hits[i] = {indices[i], std::sqrt(d2[i])};
  return hits;
}

std::vector<PointHit> PointIndex::within(const Vec3& p, double radius) const {
  std::vector<std::pair<Index, double>> matches;
  nanoflann::SearchParams params;
  params.sorted = true;
  impl_->tree.radiusSearch(p.data(), radius * radius, matches, params);
  std::vector<PointHit> hits;
  hits.reserve(matches.size());
  for (const auto& [i, d2] : matches) hits.push_back({i, std::sqrt(d2)});
  return hits;
}

// ---------------------------------------------------------------- BoxTree

std::vector<Box> element_boxes(std::span<const Vec3> nodes, const ElementBlock& elements, double relative_padding) {
  std::vector<Box> boxes(static_cast<std::size_t>(elements.size()));
  for (Index e = 0; e < elements.size(); ++e) {
    Box& b = boxes[static_cast<std::size_t>(e)];
    for (Index n : elements.element(e)) b.extend(nodes[static_cast<std::size_t>(n)]);
    b.pad(relative_padding * b.extent().norm());
  }
  return boxes;
}

BoxTree::BoxTree(std::vector<Box> boxes) : boxes_(std::move(boxes)) {
  order_.resize(boxes_.size());
  std::iota(order_.begin(), order_.end(), Index{0});
  nodes_.reserve(2 * boxes_.size() + 1);
  if (!boxes_.empty()) build(0, static_cast<Index>(boxes_.size()));
}

Index BoxTree::build(Index first, Index count) {
  constexpr Index leaf_size = 4;
  const Index id = static_cast<Index>(nodes_.size());
  nodes_.emplace_back();
  Box bounds;
  for (Index i = first; i < first + count; ++i)
    bounds.extend(boxes_[static_cast<std::size_t>(order_[static_cast<std::size_t>(i)])]);
  nodes_[static_cast<std::size_t>(id)].box = bounds;
  if (count <= leaf_size) {
    nodes_[static_cast<std::size_t>(id)].first = first;
    nodes_[static_cast<std::size_t>(id)].count = count;
    return id;
  }
  // Split at the median of the box centres along the longest axis.
  Box centres;
  for (Index i = first; i < first + count; ++i) {
    const Box& b = boxes_[static_cast<std::size_t>(order_[static_cast<std::size_t>(i)])];
    centres.extend(Vec3(0.5 * (b.lo + b.hi)));
  }
  Index axis = 0;
  centres.extent().maxCoeff(&axis);
  const auto begin = order_.begin() + first;
  const auto middle = begin + count / 2;
  std::nth_element(begin, middle, begin + count, [&](Index a, Index b) {
    const Box& ba = boxes_[static_cast<std::size_t>(a)];
    const Box& bb = boxes_[static_cast<std::size_t>(b)];
    return ba.lo[axis] + ba.hi[axis] < bb.lo[axis] + bb.hi[axis];
  });
  const Index left = build(first, count / 2);
  const Index right = build(first + count / 2, count - count / 2);
  nodes_[static_cast<std::size_t>(id)].first = left;
  nodes_[static_cast<std::size_t>(id)].right = right;
  return id;
}

void BoxTree::for_each_containing(const Vec3& p, const std::function<bool(Index)>& visit) const {
  if (nodes_.empty()) return;
  std::vector<Index> stack{0};
  while (!stack.empty()) {
    const Node& node = nodes_[static_cast<std::size_t>(stack.back())];
    stack.pop_back();
    if (!node.box.contains(p)) continue;
    if (node.count > 0) {
      for (Index i = node.first; i < node.first + node.count; ++i) {
        const Index object = order_[static_cast<std::size_t>(i)];
        if (boxes_[static_cast<std::size_t>(object)].contains(p) && !visit(object)) return;
      }
    } else {
      stack.push_back(node.right);
      stack.push_back(node.first);
    }
  }
}

std::vector<Index> BoxTree::containing(const Vec3& p) const {
  std::vector<Index> result;
  for_each_containing(p, [&](Index i) {
    result.push_back(i);
    return true;
  });
  return result;
}

PointHit BoxTree::nearest(const Vec3& p, const std::function<double(Index)>& exact_distance) const {
  PointHit best{-1, std::numeric_limits<double>::infinity()};
  if (nodes_.empty()) return best;
  using Entry = std::pair<double, Index>;  // (squared lower bound, node)
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  queue.emplace(nodes_[0].box.squared_distance(p), 0);
  while (!queue.empty()) {
    const auto [bound2, id] = queue.top();
    queue.pop();
    if (bound2 > best.distance * best.distance) break;
    const Node& node = nodes_[static_cast<std::size_t>(id)];
    if (node.count > 0) {
      for (Index i = node.first; i < node.first + node.count; ++i) {
        const Index object = order_[static_cast<std::size_t>(i)];
        if (boxes_[static_cast<std::size_t>(object)].squared_distance(p) > best.distance * best.distance) continue;
        const double d = exact_distance(object);
        if (d < best.distance) best = {object, d};
      }
    } else {
      for (Index child : {node.first, node.right})
        queue.emplace(nodes_[static_cast<std::size_t>(child)].box.squared_distance(p), child);
    }
  }
  return best;
}

// ---------------------------------------------------------------- CellLocator

CellLocator::CellLocator(const Mesh& mesh) : mesh_(mesh), tree_(element_boxes(mesh.nodes, mesh.cells, 1e-9)) {
  if (mesh.dim() != 3) {
    throw Error(fmt::format("CellLocator: the {} mesh ({}) is not a tetrahedral mesh", mesh.name, mesh.source));
  }
}

std::optional<CellLocation> CellLocator::locate(const Vec3& p, double tolerance) const {
  std::optional<CellLocation> found;
  tree_.for_each_containing(p, [&](Index e) {
    const auto v = mesh_.cells.element(e);
    const Vec3& x0 = mesh_.nodes[static_cast<std::size_t>(v[0])];
    Mat3 jacobian;
    for (int k = 0; k < 3; ++k) jacobian.col(k) = mesh_.nodes[static_cast<std::size_t>(v[k + 1])] - x0;
    const Vec3 xi = jacobian.partialPivLu().solve(p - x0);
    if (xi.minCoeff() >= -tolerance && xi.sum() <= 1.0 + tolerance) {
      found = CellLocation{e, xi};
      return false;
    }
    return true;
  });
  return found;
}

// ---------------------------------------------------------------- closest point

Vec2 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Voronoi-region walk (Ericson, Real-Time Collision Detection, 5.1.5).
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {0.0, 0.0};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {1.0, 0.0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return {d1 / (d1 - d3), 0.0};
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {0.0, 1.0};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return {0.0, d2 / (d2 - d6)};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {1.0 - w, w};  // on edge b-c
  }
  const double denom = 1.0 / (va + vb + vc);
  return {vb * denom, vc * denom};
}

SurfaceLocator::SurfaceLocator(std::span<const Vec3> nodes, const ElementBlock& triangles)
    : nodes_(nodes.begin(), nodes.end()), triangles_(triangles), tree_(element_boxes(nodes, triangles, 0.0)) {
  if (element_info(triangles.type).dim != 2) {
    throw Error("SurfaceLocator: the element block is not made of triangles");
  }
}

SurfacePoint SurfaceLocator::closest(const Vec3& p) const {
  auto vertices = [&](Index e) {
    const auto v = triangles_.element(e);
    return std::array<const Vec3*, 3>{&nodes_[static_cast<std::size_t>(v[0])], &nodes_[static_cast<std::size_t>(v[1])],
                                      &nodes_[static_cast<std::size_t>(v[2])]};
  };
  auto point_at = [&](Index e, const Vec2& xi) {
    const auto x = vertices(e);
    return Vec3(*x[0] + xi[0] * (*x[1] - *x[0]) + xi[1] * (*x[2] - *x[0]));
  };
  const PointHit hit = tree_.nearest(p, [&](Index e) {
    const auto x = vertices(e);
    return (point_at(e, closest_point_on_triangle(p, *x[0], *x[1], *x[2])) - p).norm();
  });
  SurfacePoint result;
  if (hit.index < 0) return result;
  const auto x = vertices(hit.index);
  result.element = hit.index;
  result.xi = closest_point_on_triangle(p, *x[0], *x[1], *x[2]);
  result.point = point_at(hit.index, result.xi);
  result.distance = hit.distance;
  return result;
}

}  // namespace shellflow::mesh
