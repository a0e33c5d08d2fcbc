#include "shellflow/shell/shell_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "shellflow/core/error.h"
#include "shellflow/fem/quadrature.h"
#include "shellflow/fem/reference_element.h"

namespace shellflow::shell {

Support Support::clamped(std::string group) {
  return {std::move(group), {true, true, true}, {true, true, true}, false};
}
Support Support::simply_supported(std::string group) {
  return {std::move(group), {true, true, true}, {false, false, false}, false};
}
Support Support::symmetry_plane(std::string group, int normal_axis) {
  if (normal_axis < 0 || normal_axis > 2)
    throw_input_error("symmetry plane on '{}': normal axis must be 0, 1 or 2 (got {})", group, normal_axis);
  Support s{std::move(group), {}, {}, false};
  s.fix_position[static_cast<std::size_t>(normal_axis)] = true;
  s.fix_director[static_cast<std::size_t>(normal_axis)] = true;
  return s;
}
Support Support::sliding(std::string group, int free_axis, bool clamp_director) {
  if (free_axis < 0 || free_axis > 2)
    throw_input_error("sliding support on '{}': free axis must be 0, 1 or 2 (got {})", group, free_axis);
  Support s{std::move(group), {true, true, true}, {clamp_director, clamp_director, clamp_director}, false};
  s.fix_position[static_cast<std::size_t>(free_axis)] = false;
  return s;
}

namespace {

template <class Tri>
bool is_type(mesh::ElementType t) {
  return static_cast<int>(t) == Tri::gmsh_type;
}

}  // namespace

ShellModel::ShellModel(mesh::Mesh mesh, const ShellSection& section)
    : mesh_(std::move(mesh)), section_(section) {
  section_.material.validate();
  if (!(section_.thickness > 0.0))
    throw_input_error("shell mesh '{}': thickness must be > 0 (got {})", mesh_.name, section_.thickness);
  const int type = static_cast<int>(mesh_.cells.type);
  if (type != fem::Tri3::gmsh_type && type != fem::Tri6::gmsh_type && type != fem::Tri10::gmsh_type)
    throw_input_error("shell mesh '{}': cells must be 3-, 6- or 10-node triangles (got Gmsh type {})",
                      mesh_.name, type);
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
  constrained_.assign(static_cast<std::size_t>(num_dofs()), 0);
  reference_load_ = Eigen::VectorXd::Zero(num_dofs());
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
          offsets_[((static_cast<std::size_t>(e) * n + b) * dofs_per_node + c) * n + a] =
              static_cast<int>(pos - inner);
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

template <class F>
void ShellModel::for_each_element_parallel(F&& f) const {
  for (const auto& color : colors_) {
    const auto count = static_cast<std::ptrdiff_t>(color.size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) f(color[static_cast<std::size_t>(i)]);
  }
}

bool ShellModel::assemble(const Eigen::VectorXd& u, Eigen::VectorXd& f_int, SparseMatrix* K) const {
  f_int.setZero(num_dofs());
  if (K) std::fill(K->valuePtr(), K->valuePtr() + K->nonZeros(), 0.0);
  int admissible = 1;
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
          const bool ok = internal_force(set.geometry[static_cast<std::size_t>(e)], set.rule,
                                         section_.material, ue, fe, K ? &Ke : nullptr);
          if (!ok) {
#pragma omp atomic write
            admissible = 0;
          }
          for (int j = 0; j < N; ++j)
            f_int.segment<dofs_per_node>(dofs_per_node * conn[static_cast<std::size_t>(j)]) +=
                fe.template segment<dofs_per_node>(dofs_per_node * j);
          if (K) scatter(e, Ke.data(), nd, *K);
        });
      },
      elements_);
  return admissible != 0;
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

void ShellModel::add_support(const Support& support) {
  const mesh::PhysicalGroup& group = mesh_.group(support.group);
  for (Index n : group.nodes)
    for (int i = 0; i < 3; ++i) {
      const auto base = static_cast<std::size_t>(dofs_per_node * n + i);
      if (support.fix_position[static_cast<std::size_t>(i)]) constrained_[base] = 1;
      if (support.fix_director[static_cast<std::size_t>(i)]) constrained_[base + 3] = 1;
    }
  if (support.fix_thickness_parameter)
    for (Index n : group.nodes) constrained_[static_cast<std::size_t>(dofs_per_node * n + 6)] = 1;
}

namespace {

/// Calls f(node, weight) with weight = ∫ phi_j ds0 over every edge of a group of lines
/// (4-point Gauss–Legendre, shell.md §5).
template <class F>
void integrate_over_lines(const mesh::Mesh& mesh, const mesh::PhysicalGroup& group, F&& f) {
  if (group.dim != 1)
    throw_input_error("shell mesh '{}': group '{}' must be a group of lines (dimension 1), it has dimension {}",
                      mesh.name, group.name, group.dim);
  const fem::QuadratureRule& rule = fem::line_rule(4);
  fem::visit_element_type(static_cast<int>(group.elements.type), [&](auto element) {
    using E = decltype(element);
    if constexpr (E::dim == 1) {
      constexpr int N = E::num_nodes;
      for (Index e = 0; e < group.elements.size(); ++e) {
        const auto conn = group.elements.element(e);
        for (int q = 0; q < rule.size(); ++q) {
          double phi[N], dphi[N];
          E::eval(rule.point(q).data(), phi);
          E::eval_gradients(rule.point(q).data(), dphi);
          Vec3 t = Vec3::Zero();
          for (int j = 0; j < N; ++j) t += dphi[j] * mesh.nodes[static_cast<std::size_t>(conn[static_cast<std::size_t>(j)])];
          const double ds = t.norm() * rule.weights[static_cast<std::size_t>(q)];
          for (int j = 0; j < N; ++j) f(conn[static_cast<std::size_t>(j)], phi[j] * ds);
        }
      }
    } else {
      throw_input_error("shell mesh '{}': group '{}' holds elements of dimension {}, expected lines", mesh.name,
                        group.name, E::dim);
    }
  });
}

}  // namespace

void ShellModel::add_line_load(const LineLoad& load) {
  integrate_over_lines(mesh_, mesh_.group(load.group), [&](Index node, double w) {
    reference_load_.segment<3>(dofs_per_node * node) += w * load.force_per_length;
  });
}

void ShellModel::add_point_load(const PointLoad& load) {
  if (load.node < 0 || load.node >= num_nodes())
    throw_input_error("shell point load: node {} does not exist (mesh '{}' has {} nodes)", load.node, mesh_.name,
                      num_nodes());
  reference_load_.segment<3>(dofs_per_node * load.node) += load.force;
}

void ShellModel::add_edge_couple(const EdgeCouple& couple) {
  std::vector<double> weight(static_cast<std::size_t>(num_nodes()), 0.0);
  integrate_over_lines(mesh_, mesh_.group(couple.group),
                       [&](Index node, double w) { weight[static_cast<std::size_t>(node)] += w; });
  std::vector<std::pair<Index, double>> nodes;
  for (Index n = 0; n < num_nodes(); ++n)
    if (weight[static_cast<std::size_t>(n)] != 0.0) nodes.emplace_back(n, weight[static_cast<std::size_t>(n)]);
  EdgeCouple c = couple;
  c.axis.normalize();
  edge_couples_.push_back(c);
  edge_couple_weights_.push_back(std::move(nodes));
}

void ShellModel::add_gravity(const Vec3& acceleration) {
  SparseMatrix M = make_matrix();
  assemble_mass(M);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(num_dofs());
  for (Index n = 0; n < num_nodes(); ++n) b.segment<3>(dofs_per_node * n) = acceleration;
  reference_load_ += M * b;
}

// Edge couple (shell.md §11): F_G^j = m_j (t x G_j)/|w_j|^2, w_j = G_j - (G_j.t) t, the
// gradient of m_j psi_j (psi_j: rotation angle of G_j about t), so it is conservative.
void ShellModel::add_follower_loads(const Eigen::VectorXd& u, double load_factor, Eigen::VectorXd& force,
                                    SparseMatrix* K) const {
  for (std::size_t c = 0; c < edge_couples_.size(); ++c) {
    const Vec3& t = edge_couples_[c].axis;
    Mat3 t_cross;
    t_cross << 0, -t(2), t(1), t(2), 0, -t(0), -t(1), t(0), 0;
    for (const auto& [node, weight] : edge_couple_weights_[c]) {
      const double m = load_factor * edge_couples_[c].moment_per_length * weight;
      const Vec3 G = directors_[static_cast<std::size_t>(node)] + node_director_increment(u, node);
      const Vec3 w = G - G.dot(t) * t;
      const double w2 = w.squaredNorm();
      const Vec3 txG = t.cross(G);
      force.segment<3>(dofs_per_node * node + 3) += m * txG / w2;
      if (K) {
        const Mat3 dF = m * (t_cross / w2 - 2.0 * txG * w.transpose() / (w2 * w2));
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k) K->coeffRef(dofs_per_node * node + 3 + i, dofs_per_node * node + 3 + k) -= dF(i, k);
      }
    }
  }
  // Follower pressure (shell.md §11): F_x^j = ∫ p φ_j (x̂_1 × x̂_2) dξ, load stiffness
  // ∂F_x^j/∂x_k = ∫ p φ_j (φ_k,2 [x̂_1]× − φ_k,1 [x̂_2]×) dξ.
  if (pressures_.empty()) return;
  const auto skew = [](const Vec3& v) {
    Mat3 m;
    m << 0, -v(2), v(1), v(2), 0, -v(0), -v(1), v(0), 0;
    return m;
  };
  std::visit(
      [&](const auto& set) {
        using Geometry = std::decay_t<decltype(set.geometry.front())>;
        constexpr int N = Geometry::num_nodes;
        for (const auto& [p0, cells] : pressures_) {
          const double p = load_factor * p0;
          for (Index e : cells) {
            const auto conn = mesh_.cells.element(e);
            for (int q = 0; q < set.rule.plane_size(); ++q) {
              const auto& phi = set.rule.phi[static_cast<std::size_t>(q)];
              const auto& dphi = set.rule.dphi[static_cast<std::size_t>(q)];
              const double w = p * set.rule.plane_weights[static_cast<std::size_t>(q)];
              Vec3 x1 = Vec3::Zero(), x2 = Vec3::Zero();
              for (int j = 0; j < N; ++j) {
                const Index node = conn[static_cast<std::size_t>(j)];
                const Vec3 x = mesh_.nodes[static_cast<std::size_t>(node)] + node_position_increment(u, node);
                x1 += dphi(j, 0) * x;
                x2 += dphi(j, 1) * x;
              }
              const Vec3 n = x1.cross(x2);
              const Mat3 s1 = skew(x1), s2 = skew(x2);
              for (int j = 0; j < N; ++j) {
                const Index nj = conn[static_cast<std::size_t>(j)];
                force.segment<3>(dofs_per_node * nj) += w * phi(j) * n;
                if (!K) continue;
                for (int kk = 0; kk < N; ++kk) {
                  const Index nk = conn[static_cast<std::size_t>(kk)];
                  const Mat3 dF = w * phi(j) * (dphi(kk, 1) * s1 - dphi(kk, 0) * s2);
                  for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) K->coeffRef(dofs_per_node * nj + r, dofs_per_node * nk + c) -= dF(r, c);
                }
              }
            }
          }
        }
      },
      elements_);
}

void ShellModel::add_follower_pressure(const FollowerPressure& pressure) {
  std::vector<Index> cells;
  if (pressure.group.empty()) {
    for (Index e = 0; e < mesh_.num_cells(); ++e) cells.push_back(e);
  } else {
    const mesh::PhysicalGroup& g = mesh_.group(pressure.group);
    if (g.dim != 2)
      throw_input_error("shell mesh '{}': follower pressure needs a surface group, '{}' has dimension {}", mesh_.name,
                        g.name, g.dim);
    cells = g.cells;
  }
  pressures_.emplace_back(pressure.pressure, std::move(cells));
}

Vec3 ShellModel::mean_displacement(const std::string& group, const Eigen::VectorXd& u) const {
  const mesh::PhysicalGroup& g = mesh_.group(group);
  Vec3 sum = Vec3::Zero();
  for (Index n : g.nodes) sum += node_position_increment(u, n);
  return g.nodes.empty() ? sum : Vec3(sum / static_cast<double>(g.nodes.size()));
}

}  // namespace shellflow::shell
