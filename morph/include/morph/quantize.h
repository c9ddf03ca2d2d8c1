// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file quantize.h
/// The generator's grid: move ends and tool vertices on a power-of-two grid, and planes held
/// exactly on it, so that planes that must meet (a tool facet and its neighbours at a ring
/// vertex, a silhouette plane through both ends of its tool edge) meet exactly, not up to rounding.
///
/// A point on the grid of exponent g is X·2^g with X an integer vector (job units). A plane on it,
/// IntegerPlane, is n·X = offset with an integer normal n (|n_i| ≤ 2^52, so each is an exact
/// double) and a 128-bit integer offset: it passes exactly through every grid point it was built
/// from, and translating it by a grid vector S is exact (offset + n·S). The predicates
/// (plane_predicates.h) read it as the rows [n | offset·2^g], the offset split into two doubles
/// whose sum is exact (|offset| < 2^106).
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <optional>
#include <utility>

namespace morph {

using GridPoint = std::array<std::int64_t, 3>;  ///< integer coordinates on a grid

/// A plane exactly on a grid: normal·X = offset for the grid points X of the plane (X·2^g in job
/// units). A zero normal means "not set" (the plane is only known in doubles).
struct IntegerPlane {
  // The offset first: 48 bytes, not 64 with the padding before a 16-byte-aligned offset (an
  // ExactPlane holds one, and the generator keeps millions of those).
  __int128 offset = 0;
  GridPoint normal{};
  int grid_exponent = 0;

  bool set() const { return normal[0] != 0 || normal[1] != 0 || normal[2] != 0; }
  /// The same plane moved by the grid vector `shift` (exact).
  IntegerPlane translated(const GridPoint& shift) const;
  /// The complementary halfspace: -normal·X <= -offset.
  IntegerPlane negated() const;
  /// normal·X - offset at the grid point X (exact).
  __int128 value_at(const GridPoint& point) const;
};

/// Largest normal component an IntegerPlane holds (each is then an exact double).
constexpr std::int64_t kMaxIntegerNormal = std::int64_t{1} << 52;

/// The grid exponent for a tool polytope within `max_deviation` (job units): the grid step is at
/// most max_deviation·2^-14, so snapping a point moves it by at most 1e-4 of the budget.
int grid_exponent_for(double max_deviation);

/// `x` moved to the nearest grid point (job units).
Eigen::Vector3d snap_to_grid(const Eigen::Vector3d& x, int grid_exponent);

/// The integer coordinates of `x` if it lies exactly on the grid (and within ±2^62 steps).
std::optional<GridPoint> grid_point(const Eigen::Vector3d& x, int grid_exponent);

/// The plane with normal `normal` (integers, reduced by their greatest common divisor here)
/// through the grid point `point`, or nothing when the reduced normal is zero or exceeds
/// kMaxIntegerNormal.
std::optional<IntegerPlane> plane_through(const std::array<__int128, 3>& normal, const GridPoint& point,
                                          int grid_exponent);

/// An offset as the nearest double (ties to even) and the remainder, exact for |v| < 2^106:
/// what static_cast<double>(v) and the difference give, by shifts instead of the library's
/// 128-bit conversions (which took a tenth of the predicates' time).
inline std::pair<double, double> offset_parts(__int128 v) {
  const bool negative = v < 0;
  const auto magnitude =
      negative ? static_cast<unsigned __int128>(-(v + 1)) + 1 : static_cast<unsigned __int128>(v);
  const auto top = static_cast<std::uint64_t>(magnitude >> 64);
  const int length =
      top != 0 ? 128 - __builtin_clzll(top) : 64 - __builtin_clzll(static_cast<std::uint64_t>(magnitude) | 1);
  if (length <= 53) return {static_cast<double>(static_cast<std::int64_t>(v)), 0.0};
  if (length > 106) {
    const auto high = static_cast<double>(v);
    return {high, static_cast<double>(v - static_cast<__int128>(high))};
  }
  const int shift = length - 53;
  auto kept = magnitude >> shift;
  const unsigned __int128 rest = magnitude - (kept << shift), half = static_cast<unsigned __int128>(1)
                                                                     << (shift - 1);
  if (rest > half || (rest == half && (kept & 1) != 0)) ++kept;
  // |low| ≤ 2^(shift-1) ≤ 2^52: the low 64 bits of the difference, as a signed number, are it.
  const auto low = static_cast<std::int64_t>(static_cast<std::uint64_t>(magnitude - (kept << shift)));
  const double high =
      static_cast<double>(static_cast<std::uint64_t>(kept)) * static_cast<double>(std::uint64_t{1} << shift);
  return negative ? std::pair{-high, static_cast<double>(-low)} : std::pair{high, static_cast<double>(low)};
}

/// Cross product of two integer vectors (exact for components below 2^62).
std::array<__int128, 3> integer_cross(const GridPoint& u, const GridPoint& v);

/// The grid vector divided by the greatest common divisor of its components (zero stays zero).
GridPoint reduced(const GridPoint& v);

}  // namespace morph
