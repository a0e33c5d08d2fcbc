#pragma once
// Basic numeric types shared by every module.
#include <Eigen/Dense>
#include <cstdint>

namespace shellflow {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
/// Index of a node or element inside one mesh (0-based, contiguous).
using Index = std::int32_t;

}  // namespace shellflow
