// ShellModel loads (shell.md §11): dead loads (line, point, surface traction, gravity),
// follower loads (edge couples, follower pressures with or without a time history) and the
// per-load-point pressures and tractions set from outside (coupling).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string_view>
#include <utility>

#include "shellflow/core/error.h"
#include "shellflow/fem/quadrature.h"
#include "shellflow/fem/reference_element.h"
#include "shellflow/shell/shell_model.h"
#include "shellflow/shell/shell_model_loops.h"

namespace shellflow::shell {

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
          for (int j = 0; j < N; ++j)
            t += dphi[j] * mesh.nodes[static_cast<std::size_t>(conn[static_cast<std::size_t>(j)])];
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

std::vector<Index> ShellModel::surface_cells(const std::string& group, std::string_view load_name) const {
  if (group.empty()) {
    std::vector<Index> cells(static_cast<std::size_t>(mesh_.num_cells()));
    for (Index e = 0; e < mesh_.num_cells(); ++e) cells[static_cast<std::size_t>(e)] = e;
    return cells;
  }
  const mesh::PhysicalGroup& g = mesh_.group(group);
  if (g.dim != 2)
    throw_input_error("shell mesh '{}': {} needs a surface group, '{}' has dimension {}", mesh_.name, load_name, g.name,
                      g.dim);
  return g.cells;
}

void ShellModel::add_surface_traction(const SurfaceTraction& load) {
  if (!load.traction.allFinite())
    throw_input_error("shell mesh '{}': surface traction on '{}' is not finite ({}, {}, {})", mesh_.name,
                      load.group.empty() ? "the whole shell" : load.group, load.traction.x(), load.traction.y(),
                      load.traction.z());
  if (load.traction == Vec3::Zero())
    throw_input_error("shell mesh '{}': surface traction on '{}' is zero; remove the load or give its value",
                      mesh_.name, load.group.empty() ? "the whole shell" : load.group);
  const std::vector<Index> cells = surface_cells(load.group, "surface traction");
  // F_x^j = ∫ φ_j t |X̂_1 × X̂_2| dξ on the in-plane rule of the section.
  std::visit(
      [&](const auto& set) {
        using Geometry = std::decay_t<decltype(set.geometry.front())>;
        constexpr int N = Geometry::num_nodes;
        for (Index e : cells) {
          const auto conn = mesh_.cells.element(e);
          for (int q = 0; q < set.rule.plane_size(); ++q) {
            const auto& phi = set.rule.phi[static_cast<std::size_t>(q)];
            const auto& dphi = set.rule.dphi[static_cast<std::size_t>(q)];
            Vec3 X1 = Vec3::Zero(), X2 = Vec3::Zero();
            for (int j = 0; j < N; ++j) {
              const Vec3& X = mesh_.nodes[static_cast<std::size_t>(conn[static_cast<std::size_t>(j)])];
              X1 += dphi(j, 0) * X;
              X2 += dphi(j, 1) * X;
            }
            const double dA = X1.cross(X2).norm() * set.rule.plane_weights[static_cast<std::size_t>(q)];
            for (int j = 0; j < N; ++j)
              reference_load_.segment<3>(dofs_per_node * conn[static_cast<std::size_t>(j)]) +=
                  phi(j) * dA * load.traction;
          }
        }
      },
      elements_);
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
  // An element holding each node, for the offsets of the node's director block.
  std::vector<std::pair<Index, int>> holder(static_cast<std::size_t>(num_nodes()), {-1, 0});
  const int n = mesh_.cells.nodes_per_element();
  for (Index e = mesh_.num_cells() - 1; e >= 0; --e) {
    const auto conn = mesh_.cells.element(e);
    for (int a = 0; a < n; ++a) holder[static_cast<std::size_t>(conn[static_cast<std::size_t>(a)])] = {e, a};
  }
  std::vector<std::pair<Index, double>> nodes;
  std::vector<std::array<int, 3>> offsets;
  for (Index node = 0; node < num_nodes(); ++node) {
    if (weight[static_cast<std::size_t>(node)] == 0.0) continue;
    const auto [e, a] = holder[static_cast<std::size_t>(node)];
    if (e < 0)
      throw_input_error("shell mesh '{}': edge couple on '{}': node {} belongs to no triangle", mesh_.name,
                        couple.group, node);
    nodes.emplace_back(node, weight[static_cast<std::size_t>(node)]);
    std::array<int, 3> off{};
    for (int k = 0; k < 3; ++k)
      off[static_cast<std::size_t>(k)] =
          offsets_[((static_cast<std::size_t>(e) * n + a) * dofs_per_node + 3 + k) * n + a] + 3;
    offsets.push_back(off);
  }
  EdgeCouple c = couple;
  c.axis.normalize();
  edge_couples_.push_back(c);
  edge_couple_weights_.push_back(std::move(nodes));
  edge_couple_offsets_.push_back(std::move(offsets));
}

void ShellModel::add_gravity(const Vec3& acceleration) {
  SparseMatrix M = make_matrix();
  assemble_mass(M);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(num_dofs());
  for (Index n = 0; n < num_nodes(); ++n) b.segment<3>(dofs_per_node * n) = acceleration;
  reference_load_ += M * b;
}

void ShellModel::add_follower_pressure(const FollowerPressure& pressure) {
  if (!std::isfinite(pressure.pressure))
    throw_input_error("shell mesh '{}': follower pressure on '{}' is not finite", mesh_.name,
                      pressure.group.empty() ? "the whole shell" : pressure.group);
  pressures_.push_back({pressure.pressure, pressure.history, surface_cells(pressure.group, "follower pressure")});
}

void ShellModel::set_point_pressure(std::span<const double> pressure) {
  if (pressure.size() != load_points_.size())
    throw_input_error("shell mesh '{}': {} point pressures given, the model has {} load points", mesh_.name,
                      pressure.size(), load_points_.size());
  point_pressure_.assign(pressure.begin(), pressure.end());
}

void ShellModel::set_point_traction(std::span<const Vec3> traction) {
  if (traction.size() != load_points_.size())
    throw_input_error("shell mesh '{}': {} point tractions given, the model has {} load points", mesh_.name,
                      traction.size(), load_points_.size());
  point_traction_.assign(traction.begin(), traction.end());
  // Dead: F_x^j = Σ_q φ_j(ξ_q) t_q w_q |X̂_1 × X̂_2|, assembled once here.
  point_traction_force_.setZero(num_dofs());
  std::visit(
      [&](const auto& set) {
        using Geometry = std::decay_t<decltype(set.geometry.front())>;
        constexpr int N = Geometry::num_nodes;
        const int nq = set.rule.plane_size();
        for (Index e = 0; e < mesh_.num_cells(); ++e) {
          const auto conn = mesh_.cells.element(e);
          for (int q = 0; q < nq; ++q) {
            const auto k = static_cast<std::size_t>(e) * static_cast<std::size_t>(nq) + static_cast<std::size_t>(q);
            const Vec3 f = load_points_[k].weight * point_traction_[k];
            const auto& phi = set.rule.phi[static_cast<std::size_t>(q)];
            for (int j = 0; j < N; ++j)
              point_traction_force_.segment<3>(dofs_per_node * conn[static_cast<std::size_t>(j)]) += phi(j) * f;
          }
        }
      },
      elements_);
}

void ShellModel::clear_point_loads() {
  point_pressure_.clear();
  point_traction_.clear();
  point_traction_force_.resize(0);
}

void ShellModel::check_pattern(const SparseMatrix& K, std::string_view what) const {
  if (K.rows() != num_dofs() || K.cols() != num_dofs() || !K.isCompressed() || K.nonZeros() != pattern_.nonZeros())
    throw SolverError(
        fmt::format("shell mesh '{}': {} needs a matrix with the pattern of make_matrix ({}x{}, {} "
                    "entries)",
                    mesh_.name, what, num_dofs(), num_dofs(), pattern_.nonZeros()));
}

// Edge couple (shell.md §11): F_G^j = m_j (t x G_j)/|w_j|^2, w_j = G_j - (G_j.t) t, the
// gradient of m_j psi_j (psi_j: rotation angle of G_j about t), so it is conservative. Its
// stiffness is node-diagonal: written through the precomputed offsets, serially.
void ShellModel::add_edge_couples(const Eigen::VectorXd& u, double factor, Eigen::VectorXd& force,
                                  SparseMatrix* K) const {
  for (std::size_t c = 0; c < edge_couples_.size(); ++c) {
    const Vec3& t = edge_couples_[c].axis;
    Mat3 t_cross;
    t_cross << 0, -t(2), t(1), t(2), 0, -t(0), -t(1), t(0), 0;
    for (std::size_t k = 0; k < edge_couple_weights_[c].size(); ++k) {
      const auto [node, weight] = edge_couple_weights_[c][k];
      const double m = factor * edge_couples_[c].moment_per_length * weight;
      const Vec3 G = directors_[static_cast<std::size_t>(node)] + node_director_increment(u, node);
      const Vec3 w = G - G.dot(t) * t;
      const double w2 = w.squaredNorm();
      const Vec3 txG = t.cross(G);
      force.segment<3>(dofs_per_node * node + 3) += m * txG / w2;
      if (K) {
        const Mat3 dF = m * (t_cross / w2 - 2.0 * txG * w.transpose() / (w2 * w2));
        double* values = K->valuePtr();
        for (int col = 0; col < 3; ++col)
          for (int i = 0; i < 3; ++i)
            values[edge_couple_offsets_[c][k][static_cast<std::size_t>(col)] + i] -= dF(i, col);
      }
    }
  }
}

// Follower pressure (shell.md §11): F_x^j = ∫ p φ_j (x̂_1 × x̂_2) dξ, load stiffness
// ∂F_x^j/∂x_k = ∫ p φ_j (φ_k,2 [x̂_1]× − φ_k,1 [x̂_2]×) dξ. The pressures of all groups and
// the point pressures are summed per load point first; the element loop is the coloured
// parallel one, and the stiffness goes through the element offsets.
void ShellModel::add_pressure_loads(const Eigen::VectorXd& u, const std::vector<double>& scale,
                                    bool with_point_pressure, Eigen::VectorXd& force, SparseMatrix* K) const {
  const bool points = with_point_pressure && !point_pressure_.empty();
  bool any = points;
  for (double s : scale) any = any || s != 0.0;
  if (!any) return;
  std::vector<double> p = points ? point_pressure_ : std::vector<double>(load_points_.size(), 0.0);
  const auto nq = static_cast<std::size_t>(points_per_element_);
  for (std::size_t g = 0; g < pressures_.size(); ++g) {
    if (scale[g] == 0.0) continue;
    for (Index e : pressures_[g].cells)
      for (std::size_t q = 0; q < nq; ++q) p[static_cast<std::size_t>(e) * nq + q] += scale[g];
  }
  if (K) check_pattern(*K, "the follower load stiffness");
  const auto skew = [](const Vec3& v) {
    Mat3 m;
    m << 0, -v(2), v(1), v(2), 0, -v(0), -v(1), v(0), 0;
    return m;
  };
  std::visit(
      [&](const auto& set) {
        using Geometry = std::decay_t<decltype(set.geometry.front())>;
        constexpr int N = Geometry::num_nodes;
        for_each_element_parallel([&](Index e) {
          const double* pe = p.data() + static_cast<std::size_t>(e) * nq;
          if (std::all_of(pe, pe + nq, [](double v) { return v == 0.0; })) return;
          const auto conn = mesh_.cells.element(e);
          Eigen::Matrix<double, 3, N> x, fe = Eigen::Matrix<double, 3, N>::Zero();
          for (int j = 0; j < N; ++j)
            x.col(j) = mesh_.nodes[static_cast<std::size_t>(conn[static_cast<std::size_t>(j)])] +
                       node_position_increment(u, conn[static_cast<std::size_t>(j)]);
          thread_local Eigen::Matrix<double, 3 * N, 3 * N> Ke;  // -dF/dx of the element
          if (K) Ke.setZero();
          for (std::size_t q = 0; q < nq; ++q) {
            if (pe[q] == 0.0) continue;
            const auto& phi = set.rule.phi[q];
            const auto& dphi = set.rule.dphi[q];
            const double w = pe[q] * set.rule.plane_weights[q];
            const Vec3 x1 = x * dphi.col(0), x2 = x * dphi.col(1);
            const Vec3 n = x1.cross(x2);
            for (int j = 0; j < N; ++j) fe.col(j) += (w * phi(j)) * n;
            if (!K) continue;
            const Mat3 s1 = w * skew(x1), s2 = w * skew(x2);
            for (int k = 0; k < N; ++k) {
              const Mat3 S = dphi(k, 1) * s1 - dphi(k, 0) * s2;
              for (int j = 0; j < N; ++j) Ke.template block<3, 3>(3 * j, 3 * k) -= phi(j) * S;
            }
          }
          for (int j = 0; j < N; ++j) force.segment<3>(dofs_per_node * conn[static_cast<std::size_t>(j)]) += fe.col(j);
          if (!K) return;
          double* values = K->valuePtr();
          for (int b = 0; b < N; ++b)
            for (int c = 0; c < 3; ++c) {
              const int* off = offsets_.data() + ((static_cast<std::size_t>(e) * N + b) * dofs_per_node + c) * N;
              for (int a = 0; a < N; ++a)
                for (int r = 0; r < 3; ++r) values[off[a] + r] += Ke(3 * a + r, 3 * b + c);
            }
        });
      },
      elements_);
}

void ShellModel::add_follower_loads(const Eigen::VectorXd& u, double load_factor, double time, Eigen::VectorXd& force,
                                    SparseMatrix* K) const {
  if (K && !edge_couples_.empty()) check_pattern(*K, "the edge couple stiffness");
  add_edge_couples(u, load_factor, force, K);
  std::vector<double> scale(pressures_.size());
  for (std::size_t g = 0; g < pressures_.size(); ++g)
    scale[g] = pressures_[g].history ? pressures_[g].pressure * pressures_[g].history->value(time)
                                     : load_factor * pressures_[g].pressure;
  add_pressure_loads(u, scale, true, force, K);
  if (!point_traction_.empty()) force += point_traction_force_;
}

void ShellModel::add_follower_load_direction(const Eigen::VectorXd& u, double load_factor,
                                             Eigen::VectorXd& direction) const {
  add_edge_couples(u, 1.0, direction, nullptr);
  std::vector<double> scale(pressures_.size());
  for (std::size_t g = 0; g < pressures_.size(); ++g)
    scale[g] = pressures_[g].history ? pressures_[g].pressure * pressures_[g].history->derivative(load_factor)
                                     : pressures_[g].pressure;
  add_pressure_loads(u, scale, false, direction, nullptr);
}

}  // namespace shellflow::shell
