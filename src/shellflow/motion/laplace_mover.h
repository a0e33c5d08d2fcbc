#pragma once
// Baseline fluid mesh mover: Laplacian smoothing of the displacement on the fluid mesh
// (motion.md, "Baselines"). Each update solves, per Cartesian component c,
//
//   K_FF u_F = -K_FI u_I
//
// with K the P1 (4-node tetrahedron) stiffness matrix of the *initial* fluid mesh, F the
// nodes whose component c is free and I the interface nodes (Dirichlet data from the
// boundary motion). Fixed nodes are Dirichlet with zero displacement; a node on a sliding
// (symmetry) plane with normal +-e_c has its component c fixed at zero and its other
// components free, so it stays on its plane. Hence every sliding plane must be axis-aligned.
// The mesh velocity comes from the same linear operator applied to the interface velocities.
// Solver: conjugate gradients with an incomplete-Cholesky preconditioner, warm-started from
// the previous updates: displacement guess u(t_1) + (t - t_1) v(t_1), velocity guess linearly
// extrapolated from v(t_1) and v(t_2).
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <array>
#include <span>
#include <string>
#include <vector>

#include "shellflow/motion/mesh_mover.h"

namespace shellflow::motion {

class LaplaceMover final : public FluidMeshMover {
 public:
  /// Assembles the stiffness of `fluid` (4-node tetrahedra) and factors the preconditioners.
  /// Throws InputError when the fluid mesh is not made of 4-node tetrahedra, has an element
  /// of non-positive volume, or a sliding plane is not normal to a coordinate axis.
  /// `tolerance`: CG stopping criterion |r| <= tolerance |b| (relative residual).
  LaplaceMover(const mesh::Mesh& fluid, const BoundaryGroups& groups, BoundaryMotion& motion, double tolerance = 1e-10);
  // The solvers keep references to the matrices: not copyable or movable.
  LaplaceMover(const LaplaceMover&) = delete;
  LaplaceMover& operator=(const LaplaceMover&) = delete;

  void update(double time, std::span<Vec3> x, std::span<Vec3> w) override;
  std::string name() const override { return "laplace"; }
  /// Reduced stiffness matrices, interface coupling blocks and preconditioners (all three
  /// components), plus the node lists and solution/warm-start vectors.
  std::size_t memory_bytes() const override;
  /// The warm starts of the next solves (last solutions, velocity extrapolation, their times).
  void save(ArchiveWriter& out) const override;
  void restore(ArchiveReader& in) override;

  /// Nodes whose component c is solved for (neither interface, fixed, nor on a sliding plane
  /// with normal +-e_c), in the order of the unknowns.
  std::span<const Index> free_nodes(int component) const;
  /// Largest CG iteration count and largest estimated relative residual over the solves of
  /// the last update.
  int last_iterations() const { return last_iterations_; }
  double last_error() const { return last_error_; }

 private:
  using RowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
  using Solver = Eigen::ConjugateGradient<RowMatrix, Eigen::Lower | Eigen::Upper, Eigen::IncompleteCholesky<double>>;
  struct Component {
    std::vector<Index> free;
    RowMatrix a_ff;  ///< K restricted to the free nodes
    RowMatrix a_fi;  ///< free rows, interface columns
    Solver solver;
    Eigen::VectorXd u, v;     ///< last solutions (warm start)
    Eigen::VectorXd v_older;  ///< the velocity of the update before (extrapolation)
    Eigen::VectorXd rhs, boundary;
  };

  void solve(Component& c, const Eigen::VectorXd& boundary, Eigen::VectorXd& solution);

  const mesh::Mesh& fluid_;
  FluidBoundaryNodes boundary_;
  BoundaryMotion& motion_;
  std::array<Component, 3> components_;
  int handle_ = -1;
  std::vector<Vec3> iu_, iv_;
  std::vector<Vec3> w_scratch_;          // the velocities of an update that asks for positions only
  int updates_ = 0;                      ///< updates done so far
  double t_last_ = 0.0, t_older_ = 0.0;  ///< times of the last two updates
  int last_iterations_ = 0;
  double last_error_ = 0.0;
};

}  // namespace shellflow::motion
