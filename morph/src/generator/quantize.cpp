// SPDX-License-Identifier: Apache-2.0
#include <morph/quantize.h>

#include <cmath>
#include <numeric>

namespace morph {
namespace {

__int128 magnitude(__int128 v) {
  return v < 0 ? -v : v;
}

__int128 gcd128(__int128 a, __int128 b) {
  a = magnitude(a);
  b = magnitude(b);
  while (b != 0) {
    const __int128 t = a % b;
    a = b;
    b = t;
  }
  return a;
}

}  // namespace

IntegerPlane IntegerPlane::translated(const GridPoint& shift) const {
  IntegerPlane moved = *this;
  for (int i = 0; i < 3; ++i) moved.offset += static_cast<__int128>(normal[i]) * shift[i];
  return moved;
}

IntegerPlane IntegerPlane::negated() const {
  IntegerPlane flipped = *this;
  for (std::int64_t& n : flipped.normal) n = -n;
  flipped.offset = -offset;
  return flipped;
}

__int128 IntegerPlane::value_at(const GridPoint& point) const {
  __int128 value = -offset;
  for (int i = 0; i < 3; ++i) value += static_cast<__int128>(normal[i]) * point[i];
  return value;
}

int grid_exponent_for(double max_deviation) {
  int exponent = 0;
  std::frexp(max_deviation, &exponent);  // max_deviation < 2^exponent
  return exponent - 15;
}

Eigen::Vector3d snap_to_grid(const Eigen::Vector3d& x, int grid_exponent) {
  Eigen::Vector3d snapped;
  for (int i = 0; i < 3; ++i)
    snapped[i] = std::ldexp(std::nearbyint(std::ldexp(x[i], -grid_exponent)), grid_exponent);
  return snapped;
}

std::optional<GridPoint> grid_point(const Eigen::Vector3d& x, int grid_exponent) {
  GridPoint point{};
  for (int i = 0; i < 3; ++i) {
    const double scaled = std::ldexp(x[i], -grid_exponent);
    if (!(std::fabs(scaled) < 0x1p62) || scaled != std::nearbyint(scaled)) return std::nullopt;
    point[i] = static_cast<std::int64_t>(scaled);
  }
  return point;
}

std::optional<IntegerPlane> plane_through(const std::array<__int128, 3>& normal, const GridPoint& point,
                                          int grid_exponent) {
  const __int128 divisor = gcd128(gcd128(normal[0], normal[1]), normal[2]);
  if (divisor == 0) return std::nullopt;
  IntegerPlane plane;
  plane.grid_exponent = grid_exponent;
  for (int i = 0; i < 3; ++i) {
    const __int128 n = normal[i] / divisor;
    if (magnitude(n) > kMaxIntegerNormal) return std::nullopt;
    plane.normal[i] = static_cast<std::int64_t>(n);
  }
  plane.offset = 0;
  plane.offset = plane.value_at(point);  // n·X with the offset still 0
  return plane;
}

std::array<__int128, 3> integer_cross(const GridPoint& u, const GridPoint& v) {
  using I = __int128;
  return {I(u[1]) * v[2] - I(u[2]) * v[1], I(u[2]) * v[0] - I(u[0]) * v[2], I(u[0]) * v[1] - I(u[1]) * v[0]};
}

GridPoint reduced(const GridPoint& v) {
  const std::int64_t divisor = std::gcd(std::gcd(v[0], v[1]), v[2]);
  if (divisor == 0) return v;
  return {v[0] / divisor, v[1] / divisor, v[2] / divisor};
}

}  // namespace morph
