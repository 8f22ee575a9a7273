// Plain vector type of the YADE-free physics kernels (Eigen, double precision like yade-double).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry> // cross products

namespace viscbridge {
using Vec3 = Eigen::Matrix<double, 3, 1>;
using Vec2 = Eigen::Matrix<double, 2, 1>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
constexpr double pi = 3.14159265358979323846;
} // namespace viscbridge
