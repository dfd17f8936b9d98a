#pragma once
// Basic numeric types shared by every module.
#include <Eigen/Dense>
#include <array>
#include <cstddef>
#include <numbers>

namespace narwhal {

using Real = double;
using Vec3 = Eigen::Matrix<Real, 3, 1>;
using Mat3 = Eigen::Matrix<Real, 3, 3>;

// Number of flow equations: Q = [p, u, v, w] (NUMERICS §0.3).
inline constexpr int kNumEq = 4;
using State = Eigen::Matrix<Real, kNumEq, 1>;
using Mat4 = Eigen::Matrix<Real, kNumEq, kNumEq, Eigen::RowMajor>;

template <class T>
using StateT = Eigen::Matrix<T, kNumEq, 1>;

using Index3 = std::array<int, 3>;

inline constexpr const char* kEquationNames[kNumEq] = {"p", "u", "v", "w"};

// Angles: cases and output files speak degrees, the code radians.
inline constexpr Real kRadiansPerDegree = std::numbers::pi / 180.0;
inline constexpr Real kDegreesPerRadian = 180.0 / std::numbers::pi;

}  // namespace narwhal
