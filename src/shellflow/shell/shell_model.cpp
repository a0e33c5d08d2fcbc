#include "shellflow/shell/shell_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string_view>
#include <utility>

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
  // One parallel region for all colours (the implicit barrier of `omp for` separates them).
  // Small meshes run serially: on the 40-element strip the fork/join and the barriers cost
  // more than the second thread saves (measured: 2 threads 3-10x slower on the loaded machine).
  constexpr Index min_cells_for_threads = 128;
  const bool threaded = mesh_.num_cells() >= min_cells_for_threads;
#pragma omp parallel if (threaded)
  for (const auto& color : colors_) {
    const auto count = static_cast<std::ptrdiff_t>(color.size());
#pragma omp for schedule(static)
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
      if (support.fix_position[static_cast<std::size_t>(i)]) fix_direction(n, 0, Vec3::Unit(i));
      if (support.fix_director[static_cast<std::size_t>(i)]) fix_direction(n, 1, Vec3::Unit(i));
    }
  if (support.fix_thickness_parameter)
    for (Index n : group.nodes) constrained_[static_cast<std::size_t>(dofs_per_node * n + 6)] = 1;
}

namespace {

Vec3 checked_direction(const Vec3& d, std::string_view what, std::string_view group, std::string_view mesh) {
  const double length = d.norm();
  if (!(length > 0.0) || !std::isfinite(length))
    throw_input_error(
        "shell mesh '{}': {} on group '{}' has direction ({}, {}, {}); it must be a finite vector of non-zero length",
        mesh, what, group, d.x(), d.y(), d.z());
  return d / length;
}

/// Two unit vectors completing the unit vector d to an orthonormal basis.
std::pair<Vec3, Vec3> complement(const Vec3& d) {
  const Vec3 helper = std::abs(d.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 a = d.cross(helper).normalized();
  return {a, d.cross(a)};
}

}  // namespace

DirectionalSupport DirectionalSupport::symmetry_plane(std::string group, const Vec3& normal) {
  return {std::move(group), {normal}, {normal}};
}

DirectionalSupport DirectionalSupport::roller(std::string group, const Vec3& direction, bool clamp_director) {
  DirectionalSupport s{std::move(group), {}, {}};
  if (!(direction.norm() > 0.0) || !direction.allFinite())
    throw_input_error("roller on '{}': direction ({}, {}, {}) must be a finite vector of non-zero length", s.group,
                      direction.x(), direction.y(), direction.z());
  const auto [a, b] = complement(direction.normalized());
  s.position_directions = {a, b};
  if (clamp_director) s.director_directions = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
  return s;
}

void ShellModel::add_support(const DirectionalSupport& support) {
  const mesh::PhysicalGroup& group = mesh_.group(support.group);
  std::vector<Vec3> position, director;
  for (const Vec3& d : support.position_directions)
    position.push_back(checked_direction(d, "support (position)", support.group, mesh_.name));
  for (const Vec3& d : support.director_directions)
    director.push_back(checked_direction(d, "support (director)", support.group, mesh_.name));
  for (Index n : group.nodes) {
    for (const Vec3& d : position) fix_direction(n, 0, d);
    for (const Vec3& d : director) fix_direction(n, 1, d);
  }
}

// The fixed directions of a 3-vector span a subspace with projector P. When P is diagonal
// the constraints are global components (no basis); otherwise T = [fixed directions,
// free directions] from the eigenvectors of P, and the first rank(P) local components are
// the fixed ones.
void ShellModel::fix_direction(Index node, int part, const Vec3& d) {
  const std::size_t slot = 2 * static_cast<std::size_t>(node) + static_cast<std::size_t>(part);
  Mat3& P = fixed_projector_[slot];
  const Vec3 w = d - P * d;
  if (w.norm() < 1e-9) return;  // already fixed
  P += w * w.transpose() / w.squaredNorm();
  const Index first = dofs_per_node * node + 3 * part;
  const double off_diagonal = std::max({std::abs(P(0, 1)), std::abs(P(0, 2)), std::abs(P(1, 2))});
  Mat3 T = Mat3::Identity();
  std::array<char, 3> fixed{};
  if (off_diagonal < 1e-12) {
    for (int i = 0; i < 3; ++i) fixed[static_cast<std::size_t>(i)] = P(i, i) > 0.5;
  } else {
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(P);  // eigenvalues 0 or 1, ascending
    int rank = 0;
    for (int i = 0; i < 3; ++i) rank += eig.eigenvalues()(i) > 0.5;
    for (int i = 0; i < 3; ++i) T.col(i) = eig.eigenvectors().col(2 - i);  // fixed first
    if (T.determinant() < 0.0) T.col(2) = -T.col(2);
    for (int i = 0; i < rank; ++i) fixed[static_cast<std::size_t>(i)] = 1;
  }
  for (int i = 0; i < 3; ++i) constrained_[static_cast<std::size_t>(first + i)] = fixed[static_cast<std::size_t>(i)];
  int& index = frame_index_[slot];
  if (off_diagonal < 1e-12) {
    if (index >= 0) frames_[static_cast<std::size_t>(index)].second = Mat3::Identity();
  } else if (index >= 0) {
    frames_[static_cast<std::size_t>(index)].second = T;
  } else {
    index = static_cast<int>(frames_.size());
    frames_.emplace_back(first, T);
  }
}

void ShellModel::to_local(Eigen::VectorXd& v) const {
  for (const auto& [first, T] : frames_) v.segment<3>(first) = T.transpose() * v.segment<3>(first);
}

void ShellModel::to_global(Eigen::VectorXd& v) const {
  for (const auto& [first, T] : frames_) v.segment<3>(first) = T * v.segment<3>(first);
}

void ShellModel::remove_fixed_part(Eigen::VectorXd& v) const {
  for (Index n = 0; n < num_nodes(); ++n) {
    for (int part = 0; part < 2; ++part) {
      const Mat3& P = fixed_projector_[2 * static_cast<std::size_t>(n) + static_cast<std::size_t>(part)];
      auto segment = v.segment<3>(dofs_per_node * n + 3 * part);
      segment -= P * Vec3(segment);
    }
    if (constrained_[static_cast<std::size_t>(dofs_per_node * n + 6)]) v(dofs_per_node * n + 6) = 0.0;
  }
}

double ShellModel::free_norm(const Eigen::VectorXd& v) const {
  Eigen::VectorXd free = v;
  remove_fixed_part(free);
  return free.norm();
}

double ShellModel::fixed_norm(const Eigen::VectorXd& v) const {
  Eigen::VectorXd free = v;
  remove_fixed_part(free);
  return (v - free).norm();
}

// Tᵀ K T in place. T is block diagonal with 3x3 blocks on the rotated 3-vectors; the
// pattern holds full 7x7 node blocks, so the three columns of a 3-vector have the same
// rows, and in every column the three rows of a 3-vector are consecutive entries.
void ShellModel::to_local(SparseMatrix& K) const {
  if (frames_.empty()) return;
  if (K.rows() != num_dofs() || K.cols() != num_dofs() || !K.isCompressed())
    throw SolverError(fmt::format("shell mesh '{}': to_local needs a compressed {}x{} matrix with the model's pattern",
                                  mesh_.name, num_dofs(), num_dofs()));
  double* values = K.valuePtr();
  const int* outer = K.outerIndexPtr();
  const int* inner = K.innerIndexPtr();
  const auto pattern_error = [&](Index col) {
    throw SolverError(fmt::format(
        "shell mesh '{}': to_local: column {} does not hold full 3-vector blocks (matrix not made by make_matrix)",
        mesh_.name, col));
  };
  for (const auto& [first, T] : frames_) {  // K T: columns
    const int length = outer[first + 1] - outer[first];
    if (outer[first + 2] - outer[first + 1] != length || outer[first + 3] - outer[first + 2] != length)
      pattern_error(first);
    for (int k = 0; k < length; ++k) {
      double* a = values + outer[first] + k;
      double* b = values + outer[first + 1] + k;
      double* c = values + outer[first + 2] + k;
      const Vec3 r = T.transpose() * Vec3(*a, *b, *c);
      *a = r(0);
      *b = r(1);
      *c = r(2);
    }
  }
  for (Index col = 0; col < num_dofs(); ++col) {  // Tᵀ (K T): rows
    for (int p = outer[col]; p < outer[col + 1];) {
      const int row = inner[p];
      const int component = row % dofs_per_node;
      const int index = component == 0 || component == 3
                            ? frame_index_[2 * static_cast<std::size_t>(row / dofs_per_node) + (component == 3)]
                            : -1;
      if (index < 0) {
        ++p;
        continue;
      }
      if (p + 2 >= outer[col + 1] || inner[p + 1] != row + 1 || inner[p + 2] != row + 2) pattern_error(col);
      const Mat3& T = frames_[static_cast<std::size_t>(index)].second;
      const Vec3 r = T.transpose() * Vec3(values[p], values[p + 1], values[p + 2]);
      values[p] = r(0);
      values[p + 1] = r(1);
      values[p + 2] = r(2);
      p += 3;
    }
  }
}

namespace {

/// Per node of a group of lines: the unit tangents of its edges at the node, one per
/// direction (tangents within 30° of each other, of either sign, are averaged).
std::vector<std::vector<Vec3>> line_tangents(const mesh::Mesh& mesh, const mesh::PhysicalGroup& group) {
  if (group.dim != 1)
    throw_input_error("shell mesh '{}': hard simple support needs a group of lines, '{}' has dimension {}", mesh.name,
                      group.name, group.dim);
  std::vector<std::vector<Vec3>> tangents(mesh.nodes.size());
  fem::visit_element_type(static_cast<int>(group.elements.type), [&](auto element) {
    using E = decltype(element);
    if constexpr (E::dim == 1) {
      constexpr int N = E::num_nodes;
      for (Index e = 0; e < group.elements.size(); ++e) {
        const auto conn = group.elements.element(e);
        for (int a = 0; a < N; ++a) {
          double dphi[N];
          E::eval_gradients(E::node_points[static_cast<std::size_t>(a)].data(), dphi);
          Vec3 t = Vec3::Zero();
          for (int j = 0; j < N; ++j) t += dphi[j] * mesh.nodes[static_cast<std::size_t>(conn[static_cast<std::size_t>(j)])];
          t.normalize();
          auto& list = tangents[static_cast<std::size_t>(conn[static_cast<std::size_t>(a)])];
          bool merged = false;
          for (Vec3& c : list)
            if (std::abs(c.normalized().dot(t)) > std::cos(std::numbers::pi / 6.0)) {
              c += c.dot(t) > 0.0 ? t : Vec3(-t);
              merged = true;
              break;
            }
          if (!merged) list.push_back(t);
        }
      }
    }
  });
  for (auto& list : tangents)
    for (Vec3& t : list) t.normalize();
  return tangents;
}

}  // namespace

void ShellModel::add_hard_simple_support(const std::string& group_name) {
  const mesh::PhysicalGroup& group = mesh_.group(group_name);
  const auto tangents = line_tangents(mesh_, group);
  for (Index n : group.nodes) {
    for (int i = 0; i < 3; ++i) fix_direction(n, 0, Vec3::Unit(i));
    for (const Vec3& t : tangents[static_cast<std::size_t>(n)]) fix_direction(n, 1, t);
  }
}

void ShellModel::add_prescribed_motion(const PrescribedMotion& motion) {
  const mesh::PhysicalGroup& group = mesh_.group(motion.group);
  if (!motion.displacement.allFinite())
    throw_input_error("shell mesh '{}': prescribed motion of group '{}' has a non-finite displacement", mesh_.name,
                      motion.group);
  PrescribedMotion m = motion;
  const bool rotates = motion.rotation_axis != Vec3::Zero();
  if (rotates) m.rotation_axis = checked_direction(motion.rotation_axis, "prescribed rotation", motion.group, mesh_.name);
  for (Index n : group.nodes)
    for (int i = 0; i < 3; ++i) {
      fix_direction(n, 0, Vec3::Unit(i));
      if (rotates) fix_direction(n, 1, Vec3::Unit(i));
    }
  prescribed_.push_back(std::move(m));
  prescribed_nodes_.push_back(group.nodes);
}

namespace {

/// R(g(t)) of a prescribed motion; the identity when its directors are free.
Mat3 director_rotation(const PrescribedMotion& m, double t) {
  if (m.rotation_axis == Vec3::Zero()) return Mat3::Identity();
  return Eigen::AngleAxisd(m.rotation_angle.value(t), m.rotation_axis).toRotationMatrix();
}

}  // namespace

void ShellModel::apply_prescribed(double t, Eigen::VectorXd& u) const {
  for (std::size_t k = 0; k < prescribed_.size(); ++k) {
    const PrescribedMotion& m = prescribed_[k];
    const Vec3 dx = m.displacement_history.value(t) * m.displacement;
    const bool rotates = m.rotation_axis != Vec3::Zero();
    const Mat3 R = director_rotation(m, t);
    for (Index n : prescribed_nodes_[k]) {
      u.segment<3>(dofs_per_node * n) = dx;
      if (rotates) {
        const Vec3& V = directors_[static_cast<std::size_t>(n)];
        u.segment<3>(dofs_per_node * n + 3) = R * V - V;
      }
    }
  }
}

void ShellModel::apply_prescribed_velocity(double t, Eigen::VectorXd& v) const {
  for (std::size_t k = 0; k < prescribed_.size(); ++k) {
    const PrescribedMotion& m = prescribed_[k];
    const Vec3 dx = m.displacement_history.derivative(t) * m.displacement;
    const bool rotates = m.rotation_axis != Vec3::Zero();
    const Mat3 R = director_rotation(m, t);
    const Vec3 omega = rotates ? Vec3(m.rotation_angle.derivative(t) * m.rotation_axis) : Vec3::Zero();
    for (Index n : prescribed_nodes_[k]) {
      v.segment<3>(dofs_per_node * n) = dx;
      if (rotates) v.segment<3>(dofs_per_node * n + 3) = omega.cross(R * directors_[static_cast<std::size_t>(n)]);
    }
  }
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

std::vector<Index> ShellModel::surface_cells(const std::string& group, std::string_view load_name) const {
  if (group.empty()) {
    std::vector<Index> cells(static_cast<std::size_t>(mesh_.num_cells()));
    for (Index e = 0; e < mesh_.num_cells(); ++e) cells[static_cast<std::size_t>(e)] = e;
    return cells;
  }
  const mesh::PhysicalGroup& g = mesh_.group(group);
  if (g.dim != 2)
    throw_input_error("shell mesh '{}': {} needs a surface group, '{}' has dimension {}", mesh_.name, load_name,
                      g.name, g.dim);
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
              reference_load_.segment<3>(dofs_per_node * conn[static_cast<std::size_t>(j)]) += phi(j) * dA * load.traction;
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
  std::vector<Index> cells = surface_cells(pressure.group, "follower pressure");
  pressures_.emplace_back(pressure.pressure, std::move(cells));
}

Vec3 ShellModel::mean_displacement(const std::string& group, const Eigen::VectorXd& u) const {
  const mesh::PhysicalGroup& g = mesh_.group(group);
  Vec3 sum = Vec3::Zero();
  for (Index n : g.nodes) sum += node_position_increment(u, n);
  return g.nodes.empty() ? sum : Vec3(sum / static_cast<double>(g.nodes.size()));
}

}  // namespace shellflow::shell
