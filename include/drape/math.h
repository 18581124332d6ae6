// The vector types of the library: Eigen's, in double precision.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace drape {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;
using Mat3 = Eigen::Matrix3d;

}  // namespace drape
