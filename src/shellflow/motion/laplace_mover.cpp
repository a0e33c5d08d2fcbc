#include "shellflow/motion/laplace_mover.h"

#include <algorithm>
#include <cmath>

#include "shellflow/core/error.h"
#include "shellflow/mesh/quality.h"

namespace shellflow::motion {
namespace {

using ColMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

/// P1 stiffness K_ij = sum_e V_e grad N_i . grad N_j of a mesh of 4-node tetrahedra.
ColMatrix p1_stiffness(const mesh::Mesh& fluid) {
  if (fluid.cells.type != mesh::ElementType::tet4) {
    throw_input_error(
        "{}: Laplacian mesh motion needs a fluid mesh of 4-node tetrahedra, it "
        "holds {}s; mesh it with order 1",
        fluid.source, mesh::element_info(fluid.cells.type).name);
  }
  std::vector<Eigen::Triplet<double, int>> triplets;
  triplets.reserve(static_cast<std::size_t>(fluid.num_cells()) * 16);
  for (Index e = 0; e < fluid.num_cells(); ++e) {
    const auto v = fluid.cells.element(e);
    std::array<Vec3, 4> p;
    for (int a = 0; a < 4; ++a)
      p[static_cast<std::size_t>(a)] = fluid.nodes[static_cast<std::size_t>(v[static_cast<std::size_t>(a)])];
    Mat3 jacobian;
    jacobian.col(0) = p[1] - p[0];
    jacobian.col(1) = p[2] - p[0];
    jacobian.col(2) = p[3] - p[0];
    const double det = jacobian.determinant();
    if (!(det > 0.0)) {
      throw_input_error("{}: fluid element {} has non-positive volume {:.3g} m^3; fix the mesh", fluid.source, e,
                        det / 6.0);
    }
    const Mat3 inverse = jacobian.inverse();  // rows: gradients of N_1, N_2, N_3
    std::array<Vec3, 4> grad;
    grad[1] = inverse.row(0).transpose();
    grad[2] = inverse.row(1).transpose();
    grad[3] = inverse.row(2).transpose();
    grad[0] = -(grad[1] + grad[2] + grad[3]);
    const double volume = det / 6.0;
    for (std::size_t a = 0; a < 4; ++a)
      for (std::size_t b = 0; b < 4; ++b) triplets.emplace_back(v[a], v[b], volume * grad[a].dot(grad[b]));
  }
  ColMatrix k(fluid.num_nodes(), fluid.num_nodes());
  k.setFromTriplets(triplets.begin(), triplets.end());
  return k;
}

/// Axis (0, 1, 2) a unit normal is parallel to; throws when it is not axis-aligned.
int normal_axis(const Vec3& n, const mesh::Mesh& fluid, Index node) {
  for (int c = 0; c < 3; ++c)
    if (std::abs(std::abs(n[c]) - 1.0) < 1e-9) return c;
  throw_input_error(
      "{}: sliding plane through node {} (tag {}) has normal ({:.4g}, {:.4g}, "
      "{:.4g}); the Laplacian mesh mover handles only sliding planes normal to a "
      "coordinate axis (use the space-mesh or direct IDW mover)",
      fluid.source, node, fluid.node_tags.empty() ? 0 : fluid.node_tags[static_cast<std::size_t>(node)], n.x(), n.y(),
      n.z());
}

template <class Matrix>
std::size_t sparse_bytes(const Matrix& m) {
  return static_cast<std::size_t>(m.nonZeros()) * (sizeof(double) + sizeof(int)) +
         static_cast<std::size_t>(m.outerSize() + 1) * sizeof(int);
}

}  // namespace

LaplaceMover::LaplaceMover(const mesh::Mesh& fluid, const BoundaryGroups& groups, BoundaryMotion& motion,
                           double tolerance)
    : fluid_(fluid), boundary_(classify_fluid_boundary(fluid, groups)), motion_(motion) {
  const ColMatrix k = p1_stiffness(fluid);
  const auto n = static_cast<std::size_t>(fluid.num_nodes());

  // Which components of each node are prescribed.
  std::vector<std::array<bool, 3>> prescribed(n, {false, false, false});
  for (Index i : boundary_.interface_nodes) prescribed[static_cast<std::size_t>(i)] = {true, true, true};
  for (Index i : boundary_.fixed_nodes) prescribed[static_cast<std::size_t>(i)] = {true, true, true};
  for (std::size_t s = 0; s < boundary_.sliding_nodes.size(); ++s) {
    const Index node = boundary_.sliding_nodes[s];
    for (const Vec3& normal : boundary_.sliding_normals[s]) {
      if (normal.isZero()) continue;
      prescribed[static_cast<std::size_t>(node)][static_cast<std::size_t>(normal_axis(normal, fluid, node))] = true;
    }
  }
  std::vector<int> interface_index(n, -1);
  for (std::size_t j = 0; j < boundary_.interface_nodes.size(); ++j)
    interface_index[static_cast<std::size_t>(boundary_.interface_nodes[j])] = static_cast<int>(j);

  const auto num_interface = static_cast<int>(boundary_.interface_nodes.size());
  for (std::size_t c = 0; c < 3; ++c) {
    Component& comp = components_[c];
    std::vector<int> free_index(n, -1);
    for (Index i = 0; i < fluid.num_nodes(); ++i) {
      if (prescribed[static_cast<std::size_t>(i)][c]) continue;
      free_index[static_cast<std::size_t>(i)] = static_cast<int>(comp.free.size());
      comp.free.push_back(i);
    }
    const auto num_free = static_cast<int>(comp.free.size());
    std::vector<Eigen::Triplet<double, int>> ff, fi;
    for (int col = 0; col < k.outerSize(); ++col) {
      for (ColMatrix::InnerIterator it(k, col); it; ++it) {
        const int row = free_index[static_cast<std::size_t>(it.row())];
        if (row < 0) continue;
        if (const int f = free_index[static_cast<std::size_t>(col)]; f >= 0)
          ff.emplace_back(row, f, it.value());
        else if (const int j = interface_index[static_cast<std::size_t>(col)]; j >= 0)
          fi.emplace_back(row, j, it.value());
      }
    }
    comp.a_ff.resize(num_free, num_free);
    comp.a_ff.setFromTriplets(ff.begin(), ff.end());
    comp.a_fi.resize(num_free, num_interface);
    comp.a_fi.setFromTriplets(fi.begin(), fi.end());
    comp.u = Eigen::VectorXd::Zero(num_free);
    comp.v = Eigen::VectorXd::Zero(num_free);
    comp.v_older = Eigen::VectorXd::Zero(num_free);
    comp.rhs.resize(num_free);
    comp.boundary.resize(num_interface);
    if (num_free > 0) {
      comp.solver.setTolerance(tolerance);
      comp.solver.setMaxIterations(std::max(1000, 4 * num_free));
      comp.solver.compute(comp.a_ff);
      if (comp.solver.info() != Eigen::Success) {
        throw SolverError(
            fmt::format("{}: Laplacian mesh motion: the incomplete Cholesky "
                        "factorisation of component {} failed",
                        fluid.source, c));
      }
    }
  }

  std::vector<Vec3> interface_positions;
  interface_positions.reserve(boundary_.interface_nodes.size());
  for (Index i : boundary_.interface_nodes) interface_positions.push_back(fluid.nodes[static_cast<std::size_t>(i)]);
  handle_ = motion_.register_points(interface_positions);
  iu_.resize(interface_positions.size());
  iv_.resize(interface_positions.size());
}

std::span<const Index> LaplaceMover::free_nodes(int component) const {
  return components_.at(static_cast<std::size_t>(component)).free;
}

void LaplaceMover::solve(Component& c, const Eigen::VectorXd& boundary, Eigen::VectorXd& solution) {
  c.rhs.noalias() = -(c.a_fi * boundary);
  solution = c.solver.solveWithGuess(c.rhs, solution);
  if (c.solver.info() != Eigen::Success) {
    throw SolverError(
        fmt::format("{}: Laplacian mesh motion: CG did not converge in {} "
                    "iterations (relative residual {:.3g})",
                    fluid_.source, c.solver.iterations(), c.solver.error()));
  }
  last_iterations_ = std::max(last_iterations_, static_cast<int>(c.solver.iterations()));
  last_error_ = std::max(last_error_, c.solver.error());
}

void LaplaceMover::update(double time, std::span<Vec3> x, std::span<Vec3> w_out) {
  // The velocity is solved for also when it is not wanted: it is the warm start's
  // extrapolation of the next displacement solve.
  w_scratch_.resize(x.size());
  const std::span<Vec3> w = w_out.empty() ? std::span<Vec3>(w_scratch_) : w_out;
  motion_.evaluate(handle_, time, iu_, iv_);
  const auto& X = fluid_.nodes;
  last_iterations_ = 0;
  last_error_ = 0.0;
  // Start from the prescribed values (zero displacement on fixed and sliding components).
  for (std::size_t p = 0; p < X.size(); ++p) {
    x[p] = X[p];
    w[p] = Vec3::Zero();
  }
  for (std::size_t j = 0; j < boundary_.interface_nodes.size(); ++j) {
    const auto node = static_cast<std::size_t>(boundary_.interface_nodes[j]);
    x[node] = X[node] + iu_[j];
    w[node] = iv_[j];
  }
  for (std::size_t c = 0; c < 3; ++c) {
    Component& comp = components_[c];
    if (comp.free.empty()) continue;
    const auto k = static_cast<Eigen::Index>(c);
    // Initial guesses: u(t_1) + (t - t_1) v(t_1), and v extrapolated from v(t_1), v(t_2).
    if (updates_ >= 1) comp.u += (time - t_last_) * comp.v;
    if (updates_ >= 2 && t_last_ != t_older_) {
      const double r = (time - t_last_) / (t_last_ - t_older_);
      comp.v_older = comp.v + r * (comp.v - comp.v_older);  // guess; v stays v(t_1)
      comp.v_older.swap(comp.v);                            // v: guess, v_older: v(t_1)
    } else {
      comp.v_older = comp.v;
    }
    for (std::size_t j = 0; j < iu_.size(); ++j) comp.boundary[static_cast<Eigen::Index>(j)] = iu_[j][k];
    solve(comp, comp.boundary, comp.u);
    for (std::size_t j = 0; j < iv_.size(); ++j) comp.boundary[static_cast<Eigen::Index>(j)] = iv_[j][k];
    solve(comp, comp.boundary, comp.v);
    for (std::size_t f = 0; f < comp.free.size(); ++f) {
      const auto node = static_cast<std::size_t>(comp.free[f]);
      x[node][k] = X[node][k] + comp.u[static_cast<Eigen::Index>(f)];
      w[node][k] = comp.v[static_cast<Eigen::Index>(f)];
    }
  }
  t_older_ = t_last_;
  t_last_ = time;
  ++updates_;
}

void LaplaceMover::save(ArchiveWriter& out) const {
  out.put(updates_);
  out.put(t_last_);
  out.put(t_older_);
  for (const Component& c : components_) {
    out.put(c.u);
    out.put(c.v);
    out.put(c.v_older);
  }
}

void LaplaceMover::restore(ArchiveReader& in) {
  updates_ = in.get<int>();
  t_last_ = in.get<double>();
  t_older_ = in.get<double>();
  for (Component& c : components_) {
    for (Eigen::VectorXd* v : {&c.u, &c.v, &c.v_older}) {
      Eigen::VectorXd stored = in.get_eigen();
      in.expect_size("the Laplace mover's warm start", std::size_t(stored.size()), std::size_t(v->size()));
      *v = std::move(stored);
    }
  }
}

std::size_t LaplaceMover::memory_bytes() const {
  std::size_t bytes = 0;
  for (const Component& c : components_) {
    bytes += sparse_bytes(c.a_ff) + sparse_bytes(c.a_fi);
    bytes += c.free.size() * sizeof(Index);
    bytes += static_cast<std::size_t>(c.u.size() + c.v.size() + c.v_older.size() + c.rhs.size() + c.boundary.size()) *
             sizeof(double);
    if (!c.free.empty()) {
      // Incomplete Cholesky: the factor L, the diagonal scaling and the fill-reducing
      // permutation.
      const auto& ic = c.solver.preconditioner();
      bytes += sparse_bytes(ic.matrixL()) + c.free.size() * (sizeof(double) + sizeof(int));
    }
  }
  return bytes;
}

}  // namespace shellflow::motion
