#pragma once
// Spatial search: a kd-tree over points (nanoflann), an AABB tree over boxes, and two
// queries built on them: point-in-element for tetrahedral meshes and closest point on
// a triangulated surface. Both use the elements' vertices (straight-sided geometry);
// curved cubic elements are located by Newton on their map in the motion module,
// which takes its candidates from a BoxTree.
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "shellflow/core/types.h"
#include "shellflow/mesh/mesh.h"

namespace shellflow::mesh {

struct PointHit {
  Index index = -1;
  double distance = 0.0;
};

/// kd-tree over a fixed set of points.
class PointIndex {
 public:
  explicit PointIndex(std::vector<Vec3> points);
  ~PointIndex();
  PointIndex(PointIndex&&) noexcept;
  PointIndex& operator=(PointIndex&&) noexcept;

  Index size() const;
  /// The closest point (ties: any of them).
  PointHit nearest(const Vec3& p) const;
  /// The k closest points, nearest first.
  std::vector<PointHit> nearest(const Vec3& p, int k) const;
  /// All points within `radius`, nearest first.
  std::vector<PointHit> within(const Vec3& p, double radius) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Axis-aligned box.
struct Box {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
  void extend(const Vec3& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  void extend(const Box& b) {
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  void pad(double margin) {
    lo.array() -= margin;
    hi.array() += margin;
  }
  bool contains(const Vec3& p) const { return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all(); }
  /// Squared distance from p to the box (0 inside).
  double squared_distance(const Vec3& p) const { return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).squaredNorm(); }
  Vec3 extent() const { return hi - lo; }
};

/// Bounding box of one element's nodes, padded by `relative_padding` x its diagonal
/// (curved elements may bulge a little past the hull of their nodes).
std::vector<Box> element_boxes(std::span<const Vec3> nodes, const ElementBlock& elements,
                               double relative_padding = 0.0);

/// AABB tree over a fixed list of boxes (objects are referred to by their box index).
class BoxTree {
 public:
  explicit BoxTree(std::vector<Box> boxes);

  Index size() const { return static_cast<Index>(boxes_.size()); }
  const Box& box(Index i) const { return boxes_[static_cast<std::size_t>(i)]; }
  /// Calls visit(i) for every box containing p until visit returns false.
  void for_each_containing(const Vec3& p, const std::function<bool(Index)>& visit) const;
  std::vector<Index> containing(const Vec3& p) const;
  /// Best-first search of the object closest to p. `exact_distance(i)` gives the
  /// distance from p to object i; the boxes must bound the objects.
  PointHit nearest(const Vec3& p, const std::function<double(Index)>& exact_distance) const;

 private:
  struct Node {
    Box box;
    Index first = 0;   ///< leaf: first entry in order_; inner: left child
    Index count = 0;   ///< leaf: number of boxes; inner: 0
    Index right = -1;  ///< inner: right child
  };
  Index build(Index first, Index count);

  std::vector<Box> boxes_;
  std::vector<Index> order_;
  std::vector<Node> nodes_;
};

/// Location of a point in a tetrahedral mesh: the cell and the reference coordinates
/// xi (x = x0 + (x1 - x0) xi1 + (x2 - x0) xi2 + (x3 - x0) xi3 on the cell's vertices).
struct CellLocation {
  Index cell = -1;
  Vec3 xi = Vec3::Zero();
};

/// Point-in-element queries on a tetrahedral mesh (any order; vertex geometry).
class CellLocator {
 public:
  explicit CellLocator(const Mesh& mesh);
  /// The cell containing p, up to `tolerance` in reference coordinates; nullopt when p
  /// lies outside every cell.
  std::optional<CellLocation> locate(const Vec3& p, double tolerance = 1e-10) const;

 private:
  const Mesh& mesh_;
  BoxTree tree_;
};

/// Closest point on a triangulated surface.
struct SurfacePoint {
  Index element = -1;      ///< triangle index in the block
  Vec2 xi = Vec2::Zero();  ///< reference coordinates in that triangle
  Vec3 point = Vec3::Zero();
  double distance = 0.0;
};

/// Closest point of a triangle (a, b, c) to p, as reference coordinates (xi1, xi2) with
/// point = a + xi1 (b - a) + xi2 (c - a).
Vec2 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Closest-point queries on the triangles (vertex geometry) of a block, e.g. a shell mesh
/// or a boundary group of a fluid mesh.
class SurfaceLocator {
 public:
  SurfaceLocator(std::span<const Vec3> nodes, const ElementBlock& triangles);
  SurfacePoint closest(const Vec3& p) const;

 private:
  std::vector<Vec3> nodes_;
  ElementBlock triangles_;
  BoxTree tree_;
};

}  // namespace shellflow::mesh
