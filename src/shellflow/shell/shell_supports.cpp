// ShellModel supports: axis-aligned and directional supports, local node frames, hard
// simple support, prescribed motion (shell.md §10).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string_view>
#include <utility>

#include "shellflow/core/error.h"
#include "shellflow/fem/quadrature.h"
#include "shellflow/fem/reference_element.h"
#include "shellflow/shell/shell_model.h"

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
          for (int j = 0; j < N; ++j)
            t += dphi[j] * mesh.nodes[static_cast<std::size_t>(conn[static_cast<std::size_t>(j)])];
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
  if (rotates)
    m.rotation_axis = checked_direction(motion.rotation_axis, "prescribed rotation", motion.group, mesh_.name);
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

}  // namespace shellflow::shell
