// ShellModel: construction (directors, element geometry, colouring, matrix pattern, load
// points) and assembly of the internal force, tangent and mass. Supports are in
// shell_supports.cpp, loads in shell_loads.cpp.
#include "shellflow/shell/shell_model.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <string_view>
#include <utility>

#include "shellflow/core/error.h"
#include "shellflow/fem/quadrature.h"
#include "shellflow/fem/reference_element.h"
#include "shellflow/shell/shell_model_loops.h"

namespace shellflow::shell {

namespace {

template <class Tri>
bool is_type(mesh::ElementType t) {
  return static_cast<int>(t) == Tri::gmsh_type;
}

}  // namespace

ShellModel::ShellModel(mesh::Mesh mesh, const ShellSection& section) : mesh_(std::move(mesh)), section_(section) {
  section_.material.validate();
  if (!(section_.thickness > 0.0))
    throw_input_error("shell mesh '{}': thickness must be > 0 (got {})", mesh_.name, section_.thickness);
  const int type = static_cast<int>(mesh_.cells.type);
  if (type != fem::Tri3::gmsh_type && type != fem::Tri6::gmsh_type && type != fem::Tri10::gmsh_type)
    throw_input_error("shell mesh '{}': cells must be 3-, 6- or 10-node triangles (got Gmsh type {})", mesh_.name,
                      type);
  if (mesh_.num_cells() == 0) throw_input_error("shell mesh '{}' has no triangles", mesh_.name);

  Vec3 lo = mesh_.nodes.front(), hi = lo;
  for (const Vec3& x : mesh_.nodes) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  reference_length_ = (hi - lo).norm();
  compute_directors();
  if (type == fem::Tri3::gmsh_type) elements_.emplace<ElementSet<fem::Tri3>>();
  if (type == fem::Tri6::gmsh_type) elements_.emplace<ElementSet<fem::Tri6>>();
  if (type == fem::Tri10::gmsh_type) elements_.emplace<ElementSet<fem::Tri10>>();
  std::visit([this](auto& set) { build(set); }, elements_);
  compute_pattern();
  compute_load_points();
  constrained_.assign(static_cast<std::size_t>(num_dofs()), 0);
  reference_load_ = Eigen::VectorXd::Zero(num_dofs());
  fixed_projector_.assign(2 * static_cast<std::size_t>(num_nodes()), Mat3::Zero());
  frame_index_.assign(2 * static_cast<std::size_t>(num_nodes()), -1);
}

// Nodal normals (shell.md §9): the unit normal of every element at the node's own
// parametric point, averaged with equal weights; a spread above 10° is a kink or a flipped
// element and stops the run.
void ShellModel::compute_directors() {
  fem::visit_element_type(static_cast<int>(mesh_.cells.type), [this](auto element) {
    using E = decltype(element);
    if constexpr (E::dim == 2) {
      constexpr int N = E::num_nodes;
      std::vector<Vec3> sum(mesh_.nodes.size(), Vec3::Zero());
      std::vector<std::vector<Vec3>> contributions(mesh_.nodes.size());
      for (Index e = 0; e < mesh_.num_cells(); ++e) {
        const auto conn = mesh_.cells.element(e);
        for (int a = 0; a < N; ++a) {
          double dN[2 * N];
          E::eval_gradients(E::node_points[static_cast<std::size_t>(a)].data(), dN);
          Vec3 t1 = Vec3::Zero(), t2 = Vec3::Zero();
          for (int j = 0; j < N; ++j) {
            t1 += dN[2 * j] * mesh_.nodes[static_cast<std::size_t>(conn[static_cast<std::size_t>(j)])];
            t2 += dN[2 * j + 1] * mesh_.nodes[static_cast<std::size_t>(conn[static_cast<std::size_t>(j)])];
          }
          const Vec3 n = t1.cross(t2);
          if (!(n.norm() > 0.0))
            throw_input_error("shell mesh '{}': element {} is degenerate at its node {}", mesh_.name, e, a);
          const auto node = static_cast<std::size_t>(conn[static_cast<std::size_t>(a)]);
          sum[node] += n.normalized();
          contributions[node].push_back(n.normalized());
        }
      }
      directors_.resize(mesh_.nodes.size());
      const double cos_limit = std::cos(10.0 * std::numbers::pi / 180.0);
      for (std::size_t n = 0; n < sum.size(); ++n) {
        if (contributions[n].empty()) {
          directors_[n] = Vec3::UnitZ();  // a node no element uses carries no stiffness
          continue;
        }
        directors_[n] = sum[n].normalized();
        for (const Vec3& c : contributions[n])
          if (!(c.dot(directors_[n]) > cos_limit))
            throw_input_error(
                "shell mesh '{}': element normals at node {} (tag {}) differ by more than 10° — a kink "
                "or an inconsistently oriented element; orient all triangles the same way and keep the "
                "surface smooth",
                mesh_.name, n, n < mesh_.node_tags.size() ? mesh_.node_tags[n] : n + 1);
      }
    }
  });
}

// The in-plane quadrature points of the section's rule in every element, with the reference
// geometry the pressure kernel and the point tractions use (X̂_1 × X̂_2 is oriented like V:
// the directors are averages of the element normals, checked for consistency).
void ShellModel::compute_load_points() {
  const fem::QuadratureRule& plane = fem::triangle_rule(section_.plane_degree);
  std::visit(
      [&](const auto& set) {
        using Geometry = std::decay_t<decltype(set.geometry.front())>;
        constexpr int N = Geometry::num_nodes;
        points_per_element_ = set.rule.plane_size();
        load_points_.clear();
        load_points_.reserve(static_cast<std::size_t>(mesh_.num_cells()) *
                             static_cast<std::size_t>(points_per_element_));
        for (Index e = 0; e < mesh_.num_cells(); ++e) {
          const auto conn = mesh_.cells.element(e);
          for (int q = 0; q < points_per_element_; ++q) {
            const auto& phi = set.rule.phi[static_cast<std::size_t>(q)];
            const auto& dphi = set.rule.dphi[static_cast<std::size_t>(q)];
            LoadPoint lp;
            lp.point = {e, Vec2(plane.point(q)[0], plane.point(q)[1])};
            Vec3 X1 = Vec3::Zero(), X2 = Vec3::Zero();
            for (int j = 0; j < N; ++j) {
              const Vec3& X = mesh_.nodes[static_cast<std::size_t>(conn[static_cast<std::size_t>(j)])];
              lp.position += phi(j) * X;
              X1 += dphi(j, 0) * X;
              X2 += dphi(j, 1) * X;
            }
            const Vec3 n = X1.cross(X2);
            lp.normal = n.normalized();
            lp.weight = set.rule.plane_weights[static_cast<std::size_t>(q)] * n.norm();
            load_points_.push_back(lp);
          }
        }
      },
      elements_);
}

template <class Tri>
void ShellModel::build(ElementSet<Tri>& set) {
  set.rule = ShellQuadrature<Tri>(section_.plane_degree, section_.thickness_points);
  constexpr int N = Tri::num_nodes;
  set.geometry.reserve(static_cast<std::size_t>(mesh_.num_cells()));
  for (Index e = 0; e < mesh_.num_cells(); ++e) {
    const auto conn = mesh_.cells.element(e);
    typename ShellElementGeometry<Tri>::NodeVectors X, V;
    for (int j = 0; j < N; ++j) {
      X.col(j) = mesh_.nodes[static_cast<std::size_t>(conn[static_cast<std::size_t>(j)])];
      V.col(j) = directors_[static_cast<std::size_t>(conn[static_cast<std::size_t>(j)])];
    }
    const typename ShellElementGeometry<Tri>::NodeScalars h =
        ShellElementGeometry<Tri>::NodeScalars::Constant(section_.thickness);
    set.geometry.emplace_back(X, V, h, set.rule);
    if (!(set.geometry.back().min_J0 > 0.0))
      throw_input_error(
          "shell mesh '{}': element {} has J0 = {:.3g} <= 0 at an integration point (inverted element, "
          "flipped normal, or thickness too large for the curvature)",
          mesh_.name, e, set.geometry.back().min_J0);
  }
  // Greedy colouring: no two elements of a colour share a node.
  std::vector<std::vector<char>> node_used;  // node_used[color][node]
  std::vector<int> elem_color(static_cast<std::size_t>(mesh_.num_cells()));
  for (Index e = 0; e < mesh_.num_cells(); ++e) {
    const auto conn = mesh_.cells.element(e);
    std::size_t c = 0;
    for (;; ++c) {
      if (c == node_used.size()) {
        node_used.emplace_back(mesh_.nodes.size(), 0);
        colors_.emplace_back();
      }
      bool free = true;
      for (Index n : conn) free = free && !node_used[c][static_cast<std::size_t>(n)];
      if (free) break;
    }
    for (Index n : conn) node_used[c][static_cast<std::size_t>(n)] = 1;
    colors_[c].push_back(e);
  }
}

void ShellModel::compute_pattern() {
  const int n = mesh_.cells.nodes_per_element();
  std::vector<Eigen::Triplet<double, int>> triplets;
  triplets.reserve(static_cast<std::size_t>(mesh_.num_cells()) * static_cast<std::size_t>(n * n * 49));
  for (Index e = 0; e < mesh_.num_cells(); ++e) {
    const auto conn = mesh_.cells.element(e);
    for (Index a : conn)
      for (Index b : conn)
        for (int r = 0; r < dofs_per_node; ++r)
          for (int c = 0; c < dofs_per_node; ++c)
            triplets.emplace_back(dofs_per_node * a + r, dofs_per_node * b + c, 0.0);
  }
  pattern_.resize(num_dofs(), num_dofs());
  pattern_.setFromTriplets(triplets.begin(), triplets.end());
  pattern_.makeCompressed();
  offsets_.resize(static_cast<std::size_t>(mesh_.num_cells()) * static_cast<std::size_t>(n * n * dofs_per_node));
  const int* outer = pattern_.outerIndexPtr();
  const int* inner = pattern_.innerIndexPtr();
  for (Index e = 0; e < mesh_.num_cells(); ++e) {
    const auto conn = mesh_.cells.element(e);
    for (int b = 0; b < n; ++b)
      for (int c = 0; c < dofs_per_node; ++c) {
        const int col = dofs_per_node * conn[static_cast<std::size_t>(b)] + c;
        for (int a = 0; a < n; ++a) {
          const int row = dofs_per_node * conn[static_cast<std::size_t>(a)];
          const int* pos = std::lower_bound(inner + outer[col], inner + outer[col + 1], row);
          offsets_[((static_cast<std::size_t>(e) * n + b) * dofs_per_node + c) * n + a] = static_cast<int>(pos - inner);
        }
      }
  }
}

SparseMatrix ShellModel::make_matrix() const { return pattern_; }

void ShellModel::scatter(Index e, const double* Ke, int nd, SparseMatrix& K) const {
  // Ke is column-major nd x nd, nd = 7 n.
  const int n = nd / dofs_per_node;
  double* values = K.valuePtr();
  for (int b = 0; b < n; ++b)
    for (int c = 0; c < dofs_per_node; ++c) {
      const double* column = Ke + static_cast<std::ptrdiff_t>(dofs_per_node * b + c) * nd;
      const int* off = offsets_.data() + ((static_cast<std::size_t>(e) * n + b) * dofs_per_node + c) * n;
      for (int a = 0; a < n; ++a)
        for (int r = 0; r < dofs_per_node; ++r) values[off[a] + r] += column[dofs_per_node * a + r];
    }
}

bool ShellModel::assemble(const Eigen::VectorXd& u, Eigen::VectorXd& f_int, SparseMatrix* K) const {
  f_int.setZero(num_dofs());
  if (K) std::fill(K->valuePtr(), K->valuePtr() + K->nonZeros(), 0.0);
  std::atomic<bool> admissible = true;
  std::visit(
      [&](const auto& set) {
        using Geometry = std::decay_t<decltype(set.geometry.front())>;
        constexpr int N = Geometry::num_nodes;
        constexpr int nd = Geometry::num_dofs;
        for_each_element_parallel([&](Index e) {
          const auto conn = mesh_.cells.element(e);
          Eigen::Matrix<double, nd, 1> ue, fe;
          for (int j = 0; j < N; ++j)
            ue.template segment<dofs_per_node>(dofs_per_node * j) =
                u.segment<dofs_per_node>(dofs_per_node * conn[static_cast<std::size_t>(j)]);
          // The element matrix is large for Tri10 (39 kB): keep it off the stack.
          thread_local Eigen::Matrix<double, nd, nd> Ke;
          const bool ok = internal_force(set.geometry[static_cast<std::size_t>(e)], set.rule, section_.material, ue, fe,
                                         K ? &Ke : nullptr);
          if (!ok) admissible.store(false, std::memory_order_relaxed);
          for (int j = 0; j < N; ++j)
            f_int.segment<dofs_per_node>(dofs_per_node * conn[static_cast<std::size_t>(j)]) +=
                fe.template segment<dofs_per_node>(dofs_per_node * j);
          if (K) scatter(e, Ke.data(), nd, *K);
        });
      },
      elements_);
  return admissible.load();
}

double ShellModel::strain_energy(const Eigen::VectorXd& u) const {
  double U = 0.0;
  std::visit(
      [&](const auto& set) {
        using Geometry = std::decay_t<decltype(set.geometry.front())>;
        constexpr int N = Geometry::num_nodes;
        constexpr int nd = Geometry::num_dofs;
        for (Index e = 0; e < mesh_.num_cells(); ++e) {
          const auto conn = mesh_.cells.element(e);
          Eigen::Matrix<double, nd, 1> ue;
          for (int j = 0; j < N; ++j)
            ue.template segment<dofs_per_node>(dofs_per_node * j) =
                u.segment<dofs_per_node>(dofs_per_node * conn[static_cast<std::size_t>(j)]);
          U += shell::strain_energy(set.geometry[static_cast<std::size_t>(e)], set.rule, section_.material, ue);
        }
      },
      elements_);
  return U;
}

void ShellModel::assemble_mass(SparseMatrix& M) const {
  std::fill(M.valuePtr(), M.valuePtr() + M.nonZeros(), 0.0);
  std::visit(
      [&](const auto& set) {
        using Geometry = std::decay_t<decltype(set.geometry.front())>;
        constexpr int nd = Geometry::num_dofs;
        for_each_element_parallel([&](Index e) {
          thread_local Eigen::Matrix<double, nd, nd> Me;
          Me = mass_matrix(set.geometry[static_cast<std::size_t>(e)], set.rule, section_.material.density);
          scatter(e, Me.data(), nd, M);
        });
      },
      elements_);
}

Vec3 ShellModel::mean_displacement(const std::string& group, const Eigen::VectorXd& u) const {
  const mesh::PhysicalGroup& g = mesh_.group(group);
  Vec3 sum = Vec3::Zero();
  for (Index n : g.nodes) sum += node_position_increment(u, n);
  return g.nodes.empty() ? sum : Vec3(sum / static_cast<double>(g.nodes.size()));
}

}  // namespace shellflow::shell
