// SPDX-License-Identifier: Apache-2.0
#include <morph/plane_predicates.h>

#include <Eigen/Geometry>

#include "generator/double_double_filter.h"
#include "generator/exact_determinant.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

namespace morph {
namespace {

using exact::ExactRows;
using exact::Row;  // normal, offset

constexpr double kUnit = DBL_EPSILON / 2;  // unit roundoff
// vertex_point()'s Cramer rule is within the margin of the float looks (RoughCorners) only with
// a long double of 64 bits of mantissa or more (x87's 80 bits on amd64): with 53, its error on
// corners of small determinants is thousands of times larger, and the looks would decide wrongly.
// (Valgrind computes long double as double: under it a whole job such as bear.nc fails.)
static_assert(LDBL_MANT_DIG >= 64, "vertex_point() needs a long double of at least 64 bits of mantissa");
// Error bounds of the evaluation orders below: a 3×3 determinant by cofactors is within
// 5u(1+u)^5 of its permanent (the same sum with absolute values; two products and two sums
// deep); the 4×4, the offsets times those cofactors, adds each cofactor's bound times its offset
// and 4u(1+u)^4 of the sum of |offset·cofactor| (a product and three sums). Rounded up, which
// also covers the rounding of the bounds' own evaluation.
constexpr double kDet3Bound = 8 * kUnit;
constexpr double kDet4Bound = 8 * kUnit;
// Below this the bounds could underflow: such inputs go to exact arithmetic.
constexpr double kTiny = DBL_MIN * 1e20;

// The row the predicates decide on, and the low part of its offset (0 unless exact): an exact
// plane's normal components are integers below 2^52 (exact doubles) and its offset·2^g is split
// into the nearest double and the remainder, exact because |offset| < 2^106 (quantize.h).
struct ExactRow {
  Row row;
  double offset_low = 0.0;
};

// 2^e for a normal exponent (the grid's), without ldexp's generality.
double power_of_two(int e) {
  const std::uint64_t bits = static_cast<std::uint64_t>(e + 1023) << 52;
  double v;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

ExactRow row_of(const ExactPlane& p) {
  if (!p.exact.set()) return {{p.normal.x(), p.normal.y(), p.normal.z(), p.offset}, 0.0};
  const IntegerPlane& q = p.exact;
  const double scale = power_of_two(q.grid_exponent);
  const auto [high, low] = offset_parts(q.offset);
  return {{static_cast<double>(q.normal[0]), static_cast<double>(q.normal[1]),
           static_cast<double>(q.normal[2]), high * scale},
          low * scale};
}

// row_of()'s normal with a zero offset, for the predicates that read the normals alone.
Row normal_row(const ExactPlane& p) {
  if (!p.exact.set()) return {p.normal.x(), p.normal.y(), p.normal.z(), 0.0};
  return {static_cast<double>(p.exact.normal[0]), static_cast<double>(p.exact.normal[1]),
          static_cast<double>(p.exact.normal[2]), 0.0};
}

// The planes' integer forms when all are exact on one grid (then the integers decide directly).
template <std::size_t N>
bool on_one_grid(const std::array<const ExactPlane*, N>& planes) {
  for (const ExactPlane* p : planes)
    if (!p->exact.set() || p->exact.grid_exponent != planes[0]->exact.grid_exponent) return false;
  return true;
}

int sign(double v) {
  return (v > 0) - (v < 0);
}

struct Filtered {
  double value, bound;
  // The sign if the filter decides it, else 0.
  int certain() const {
    if (!std::isfinite(value) || !std::isfinite(bound) || bound < kTiny) return 0;
    return std::fabs(value) > bound ? sign(value) : 0;
  }
};

// det of the normals of rows i, j, k (in that order).
Filtered det3(const Row& a, const Row& b, const Row& c) {
  const double m0 = b[1] * c[2] - b[2] * c[1], m1 = b[0] * c[2] - b[2] * c[0], m2 = b[0] * c[1] - b[1] * c[0];
  const double p0 = std::fabs(b[1] * c[2]) + std::fabs(b[2] * c[1]);
  const double p1 = std::fabs(b[0] * c[2]) + std::fabs(b[2] * c[0]);
  const double p2 = std::fabs(b[0] * c[1]) + std::fabs(b[1] * c[0]);
  const double permanent = std::fabs(a[0]) * p0 + std::fabs(a[1]) * p1 + std::fabs(a[2]) * p2;
  return {a[0] * m0 - a[1] * m1 + a[2] * m2, kDet3Bound * permanent};
}

int exact_normals_orientation(const Row& a, const Row& b, const Row& c) {
  if (int s = exact::double_double_minor_sign(a, b, c)) {
    ++predicate_counts().refined;
    return s;
  }
  ++predicate_counts().exact;
  return ExactRows({a, b, c, Row{}}, 3).minor_sign(0, 1, 2);
}

// Sign of det[normals of a, b, c], given their rows and the filter's look at it.
int orientation_of(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c, const Row& ra,
                   const Row& rb, const Row& rc, const Filtered& filtered) {
  if (int s = filtered.certain()) return s;
  if (on_one_grid(std::array<const ExactPlane*, 3>{&a, &b, &c})) {
    ++predicate_counts().exact;
    return exact::integer_minor_sign(a.exact, b.exact, c.exact);
  }
  return exact_normals_orientation(ra, rb, rc);
}

// A 3×3 determinant by cofactors along the first row, in long double.
long double det3_of(const long double m[3][3]) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

// The four planes as rows of [normal | offset]: the cofactors of the offset column, the
// determinant, and their exact forms on demand.
class FourPlanes {
 public:
  explicit FourPlanes(const std::array<const ExactPlane*, 4>& planes) : planes_(planes) {
    std::array<ExactRow, 4> rows;
    for (int i = 0; i < 4; ++i) rows[i] = row_of(*planes[i]);
    if (on_one_grid(planes))
      for (int i = 0; i < 4; ++i) integer_[i] = &planes[i]->exact;
    for (int i = 0; i < 4; ++i) {
      rows_[i] = rows[i].row;
      low_[i] = rows[i].offset_low;
      has_low_ = has_low_ || low_[i] != 0.0;
    }
    for (int i = 0; i < 4; ++i) {
      const auto [a, b, c] = others(i);
      Filtered m = det3(rows_[a], rows_[b], rows_[c]);
      const double s = (i % 2 == 0) ? -1.0 : 1.0;  // (-1)^(i+3)
      cofactor_[i] = {s * m.value, m.bound};
    }
  }
  // Sign of det[normals | offsets].
  // `vertex_off_grid`: the caller found the vertex of the first three is no grid point.
  int determinant_sign(bool vertex_off_grid = false) {
    double value = 0, bound = 0;
    for (int i = 0; i < 4; ++i) {
      value += rows_[i][3] * cofactor_[i].value;
      // the cofactor's own error, carried through, and the rounding of the product and sums
      bound += std::fabs(rows_[i][3]) * (cofactor_[i].bound + kDet4Bound * std::fabs(cofactor_[i].value));
      // an exact plane's low offset part, left out of the value (|low| ≤ u·|offset|)
      bound += 1.01 * std::fabs(low_[i]) * (std::fabs(cofactor_[i].value) + cofactor_[i].bound);
    }
    if (int s = Filtered{value, bound}.certain()) return s;
    // Planes on one grid that the filter cannot tell apart mostly meet at a grid point, a tool
    // vertex where several facets meet, exactly (a tie): the grid point decides that at once,
    // where the double-word filter would only fail.
    if (integer_[0]) {
      ++predicate_counts().exact;
      if (!vertex_off_grid)
        if (const std::optional<int> s = grid_vertex_sign()) return *s;
      return exact::integer_det4_sign(integer_);
    }
    // The double-word filter reads one double per offset: rows with a low part go to the integers.
    if (int s = has_low_ ? 0 : exact::double_double_det4_sign(rows_)) {
      ++predicate_counts().refined;
      return s;
    }
    ++predicate_counts().exact;
    return exact().det4_sign();
  }
  // Sign of det[normals of rows 0, 1, 2] (normals_orientation() of the first three planes; the
  // filter's look at it is the cofactor of row 3, whose sign (-1)^(3+3) is +1).
  int orientation() const {
    return orientation_of(*planes_[0], *planes_[1], *planes_[2], rows_[0], rows_[1], rows_[2], cofactor_[3]);
  }
  // determinant_sign() for four planes on one grid when the vertex of the first three is a grid
  // point X (the filter fails mostly at ties, and those are mostly at a tool vertex where several
  // facets meet): det = -det3(normals 0..2)·(n3·x - o3) with x = X·2^g, so the sign is that of
  // plane 3's integer value at X; the three planes' values there being zero proves X is their
  // vertex. Nothing when the rounded vertex does not snap to such a point.
  std::optional<int> grid_vertex_sign() const {
    const int orientation = this->orientation();
    if (orientation == 0) return std::nullopt;
    using L = long double;
    L n[3][3], o[3];
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k) n[r][k] = rows_[r][k];
      o[r] = static_cast<L>(rows_[r][3]) + static_cast<L>(low_[r]);
    }
    const L d = det3_of(n);
    Eigen::Vector3d x;
    for (int col = 0; col < 3; ++col) {
      L m[3][3];
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) m[r][k] = (k == col) ? o[r] : n[r][k];
      x[col] = static_cast<double>(det3_of(m) / d);
    }
    // The nearest grid point (scaling by a power of two is exact; a wrong point fails the check).
    const double scale = std::ldexp(1.0, -integer_[0]->grid_exponent);
    GridPoint point{};
    for (int i = 0; i < 3; ++i) {
      const double steps = std::nearbyint(x[i] * scale);
      if (!(std::fabs(steps) < 0x1p62)) return std::nullopt;
      point[i] = static_cast<std::int64_t>(steps);
    }
    for (int r = 0; r < 3; ++r)
      if (integer_[r]->value_at(point) != 0) return std::nullopt;
    const __int128 value = integer_[3]->value_at(point);
    return value == 0 ? 0 : (value > 0 ? -orientation : orientation);
  }
  // Sign of the cofactor of row i's offset.
  int cofactor_sign(int i) {
    if (int s = cofactor_[i].certain()) return s;
    const auto [a, b, c] = others(i);
    int minor = 0;
    if (integer_[0]) {
      ++predicate_counts().exact;
      minor = exact::integer_minor_sign(*integer_[a], *integer_[b], *integer_[c]);
    } else if ((minor = exact::double_double_minor_sign(rows_[a], rows_[b], rows_[c])) != 0) {
      ++predicate_counts().refined;
    } else {
      ++predicate_counts().exact;
      minor = exact().minor_sign(a, b, c);
    }
    return (i % 2 == 0) ? -minor : minor;
  }

 private:
  static std::array<int, 3> others(int i) {
    std::array<int, 3> o{};
    for (int k = 0, n = 0; k < 4; ++k)
      if (k != i) o[n++] = k;
    return o;
  }
  const ExactRows& exact() {
    if (!exact_) exact_.emplace(rows_, 4, low_);
    return *exact_;
  }

  std::array<const ExactPlane*, 4> planes_;
  std::array<Row, 4> rows_;
  std::array<const IntegerPlane*, 4> integer_{};  // all set when the four are on one grid
  std::array<double, 4> low_{};
  bool has_low_ = false;
  std::array<Filtered, 4> cofactor_{};
  std::optional<ExactRows> exact_;
};

// The vertex of three planes by Cramer's rule in long double, from the exact forms where there
// are (integer normals are exact in long double; the offset rounds once), so vertices of
// different triples at one exact point round alike. When `error` is given, it receives a bound
// on the distance from the exact vertex (infinity when none can be given): a forward error
// analysis, as for the filters above, in long double's unit roundoff U. A 3×3 determinant by
// cofactors is within 5U(1+U)^5 of its permanent P (taken 8U·P, which covers the rounding of
// P's own evaluation); replacing a column by the offsets adds U·P for their rounding (a cofactor
// is at most its minor's permanent). With those bounds EN of the numerator N and ED < |D| of the
// denominator D, |N/D - N'/D'| <= (EN·|D'| + |N'|·ED) / (|D'|·(|D'| - ED)), primes the computed
// values; the quotient and its rounding to double add 2^-52 of the coordinate.
Eigen::Vector3d cramer(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c, double* error) {
  const std::array<ExactRow, 3> rows{row_of(a), row_of(b), row_of(c)};
  if (orientation_of(a, b, c, rows[0].row, rows[1].row, rows[2].row,
                     det3(rows[0].row, rows[1].row, rows[2].row)) == 0)
    throw std::invalid_argument("vertex_point: the three planes have no single common point");
  using L = long double;
  L n[3][3], o[3];
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) n[r][k] = rows[r].row[k];
    o[r] = static_cast<L>(rows[r].row[3]) + static_cast<L>(rows[r].offset_low);
  }
  auto permanent = [](const L m[3][3]) {
    using std::fabs;
    return fabs(m[0][0]) * (fabs(m[1][1] * m[2][2]) + fabs(m[1][2] * m[2][1])) +
           fabs(m[0][1]) * (fabs(m[1][0] * m[2][2]) + fabs(m[1][2] * m[2][0])) +
           fabs(m[0][2]) * (fabs(m[1][0] * m[2][1]) + fabs(m[1][1] * m[2][0]));
  };
  constexpr L kUnitL = std::numeric_limits<L>::epsilon() / 2;
  const L d = det3_of(n);
  const L d_error = error ? 8 * kUnitL * permanent(n) : 0;
  const bool bounded = error && d_error < std::fabs(d);
  L squared = 0;
  Eigen::Vector3d x;
  for (int col = 0; col < 3; ++col) {
    L m[3][3];
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) m[r][k] = (k == col) ? o[r] : n[r][k];
    const L numerator = det3_of(m);
    x[col] = static_cast<double>(numerator / d);
    if (bounded) {
      const L n_error = 10 * kUnitL * permanent(m);
      const L e = (n_error * std::fabs(d) + std::fabs(numerator) * d_error) /
                      (std::fabs(d) * (std::fabs(d) - d_error)) +
                  std::fabs(static_cast<L>(x[col])) * (DBL_EPSILON * 2);
      squared += e * e;
    }
  }
  if (error)
    // Doubled for the rounding of the bound's own evaluation.
    *error = bounded ? static_cast<double>(2 * std::sqrt(squared)) : std::numeric_limits<double>::infinity();
  return x;
}

}  // namespace

PredicateCounts& predicate_counts() {
  thread_local PredicateCounts counts;
  return counts;
}

int normals_orientation(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c) {
  // The normals alone: splitting the offsets (row_of()) was most of this predicate's cost.
  const Row ra = normal_row(a), rb = normal_row(b), rc = normal_row(c);
  return orientation_of(a, b, c, ra, rb, rc, det3(ra, rb, rc));
}

namespace {

// side_at_vertex(); `vertex_off_grid` as FourPlanes::determinant_sign() takes it.
int side_at_vertex(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c, const ExactPlane& d,
                   bool vertex_off_grid) {
  ++predicate_counts().calls;
  FourPlanes four({&a, &b, &c, &d});  // its rows also give the orientation of a, b, c
  const int orientation = four.orientation();
  if (orientation == 0)
    throw std::invalid_argument("side_at_vertex: the three planes have no single common point");
  if (d.rank == a.rank || d.rank == b.rank || d.rank == c.rank) return 0;
  // det[n|o] = -det3(a,b,c)·(d.normal·x - d.offset), x the vertex (Schur complement).
  int det = four.determinant_sign(vertex_off_grid);
  if (det == 0) {
    // Offsets o_i + direction_i·ε_rank_i: det[n|o+δ] = Σ δ_i·cofactor_i, decided by the
    // dominant (smallest) rank with a non-zero cofactor; d's own cofactor is ±det3(a,b,c) ≠ 0.
    ++predicate_counts().ties;
    const std::array<const ExactPlane*, 4> planes{&a, &b, &c, &d};
    std::array<int, 4> order{0, 1, 2, 3};
    std::sort(order.begin(), order.end(), [&](int i, int j) { return planes[i]->rank < planes[j]->rank; });
    for (int i : order)
      if (int s = four.cofactor_sign(i)) {
        det = planes[i]->direction * s;
        break;
      }
  }
  return -det * orientation;
}

}  // namespace

int side_at_vertex(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c, const ExactPlane& d) {
  return side_at_vertex(a, b, c, d, false);
}

std::optional<GridPoint> grid_vertex(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c) {
  if (!on_one_grid(std::array<const ExactPlane*, 3>{&a, &b, &c})) return std::nullopt;
  const std::array<ExactRow, 3> rows{row_of(a), row_of(b), row_of(c)};
  if (orientation_of(a, b, c, rows[0].row, rows[1].row, rows[2].row,
                     det3(rows[0].row, rows[1].row, rows[2].row)) == 0)
    return std::nullopt;
  using L = long double;
  L n[3][3], o[3];
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) n[r][k] = rows[r].row[k];
    o[r] = static_cast<L>(rows[r].row[3]) + static_cast<L>(rows[r].offset_low);
  }
  const L d = det3_of(n);
  // The nearest grid point to Cramer's (scaling by a power of two is exact; a wrong point fails
  // the check below).
  const double scale = std::ldexp(1.0, -a.exact.grid_exponent);
  GridPoint point{};
  for (int col = 0; col < 3; ++col) {
    L m[3][3];
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) m[r][k] = (k == col) ? o[r] : n[r][k];
    const double steps = std::nearbyint(static_cast<double>(det3_of(m) / d) * scale);
    if (!(std::fabs(steps) < 0x1p62)) return std::nullopt;
    point[col] = static_cast<std::int64_t>(steps);
  }
  for (const ExactPlane* p : {&a, &b, &c})
    if (p->exact.value_at(point) != 0) return std::nullopt;
  return point;
}

std::optional<GridPoint> grid_vertex_near(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c,
                                          const Eigen::Vector3d& near) {
  if (!on_one_grid(std::array<const ExactPlane*, 3>{&a, &b, &c})) return std::nullopt;
  const double scale = std::ldexp(1.0, -a.exact.grid_exponent);
  GridPoint point{};
  for (int i = 0; i < 3; ++i) {
    const double steps = std::nearbyint(near[i] * scale);
    if (!(std::fabs(steps) < 0x1p62)) return std::nullopt;
    point[i] = static_cast<std::int64_t>(steps);
  }
  for (const ExactPlane* p : {&a, &b, &c})
    if (p->exact.value_at(point) != 0) return std::nullopt;
  if (normals_orientation(a, b, c) == 0) return std::nullopt;
  return point;
}

int side_at_vertex_near(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c,
                        const Eigen::Vector3d& near, VertexGrid& grid, const ExactPlane& d) {
  if (d.exact.set() && a.exact.set() && d.exact.grid_exponent == a.exact.grid_exponent) {
    if (!grid.looked_for) {
      grid.point = grid_vertex_near(a, b, c, near);
      grid.looked_for = true;
    }
    if (grid.point) return side_at_grid_vertex(a, b, c, *grid.point, d);
    // Not a grid point: the integers decide without looking for one again.
    return side_at_vertex(a, b, c, d, true);
  }
  return side_at_vertex(a, b, c, d, false);
}

int side_at_grid_vertex(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c, const GridPoint& x,
                        const ExactPlane& d) {
  ++predicate_counts().calls;
  if (d.rank == a.rank || d.rank == b.rank || d.rank == c.rank) return 0;
  const __int128 value = d.exact.value_at(x);
  if (value != 0) return value > 0 ? 1 : -1;
  // As side_at_vertex() settles a tie: det[n|o+δ] = Σ δ_i·cofactor_i, the dominant (smallest)
  // rank with a non-zero cofactor deciding; a cofactor of the offsets' column is ± a minor of
  // the normals, and the result is -det·orientation.
  ++predicate_counts().ties;
  const std::array<const ExactPlane*, 4> planes{&a, &b, &c, &d};
  auto normals = [](const ExactPlane& p) {
    return Row{static_cast<double>(p.exact.normal[0]), static_cast<double>(p.exact.normal[1]),
               static_cast<double>(p.exact.normal[2]), 0.0};
  };
  const std::array<Row, 4> rows{normals(a), normals(b), normals(c), normals(d)};
  auto minor_without = [&](int i) {
    std::array<int, 3> o{};
    for (int k = 0, m = 0; k < 4; ++k)
      if (k != i) o[m++] = k;
    return orientation_of(*planes[o[0]], *planes[o[1]], *planes[o[2]], rows[o[0]], rows[o[1]], rows[o[2]],
                          det3(rows[o[0]], rows[o[1]], rows[o[2]]));
  };
  const int orientation = minor_without(3);
  if (orientation == 0)
    throw std::invalid_argument("side_at_grid_vertex: the three planes have no single common point");
  std::array<int, 4> order{0, 1, 2, 3};
  std::sort(order.begin(), order.end(), [&](int i, int j) { return planes[i]->rank < planes[j]->rank; });
  for (int i : order) {
    const int minor = i == 3 ? orientation : minor_without(i);
    if (const int cofactor = (i % 2 == 0) ? -minor : minor)
      return -planes[i]->direction * cofactor * orientation;
  }
  return 0;  // not reached: d's own cofactor is the orientation
}

int limit_side_at_vertex(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c, const ExactPlane& d) {
  ++predicate_counts().calls;
  FourPlanes four({&a, &b, &c, &d});
  const int orientation = four.orientation();
  if (orientation == 0)
    throw std::invalid_argument("limit_side_at_vertex: the three planes have no single common point");
  if (d.rank == a.rank || d.rank == b.rank || d.rank == c.rank) return 0;
  return -four.determinant_sign() * orientation;
}

int limit_side_at_grid_vertex(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c,
                              const GridPoint& x, const ExactPlane& d) {
  if (d.rank == a.rank || d.rank == b.rank || d.rank == c.rank) return 0;
  if (!d.exact.set() || d.exact.grid_exponent != a.exact.grid_exponent)
    return limit_side_at_vertex(a, b, c, d);
  ++predicate_counts().calls;
  const __int128 value = d.exact.value_at(x);
  return value == 0 ? 0 : (value > 0 ? 1 : -1);
}

bool same_limit_point(const PlaneTriple& u, const PlaneTriple& v) {
  for (std::size_t k = 0; k < 3; ++k)
    if (limit_side_at_vertex(u[0], u[1], u[2], v[k]) != 0) return false;
  return true;
}

bool same_limit_point(const PlaneTriple& u, const PlaneTriple& v, const Eigen::Vector3d& near_u) {
  const std::optional<GridPoint> x = grid_vertex_near(u[0], u[1], u[2], near_u);
  if (!x) return same_limit_point(u, v);
  for (std::size_t k = 0; k < 3; ++k)
    if (limit_side_at_grid_vertex(u[0], u[1], u[2], *x, v[k]) != 0) return false;
  return true;
}

Eigen::Vector3d vertex_point(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c) {
  // Where the normals are nearly dependent (three planes nearly through one line, as a tool
  // facet, its neighbour and the silhouette plane of their common edge), long double Cramer can
  // be off by far more than the tolerance; there the exact rational, rounded.
  double error = 0.0;
  const Eigen::Vector3d x = cramer(a, b, c, &error);
  if (error <= 1e-12 * (1.0 + x.cwiseAbs().maxCoeff())) return x;
  const ExactRow ra = row_of(a), rb = row_of(b), rc = row_of(c);
  const std::array<double, 3> exact = exact::ExactRows({ra.row, rb.row, rc.row, exact::Row{}}, 3,
                                                       {ra.offset_low, rb.offset_low, rc.offset_low, 0.0})
                                          .meeting_point();
  return Eigen::Vector3d(exact[0], exact[1], exact[2]);
}

Eigen::Vector3d conditioned_vertex_point(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c) {
  return cramer(a, b, c, nullptr);
}

std::optional<Eigen::Vector3d> look_vertex_point(const ExactPlane& a, const ExactPlane& b,
                                                 const ExactPlane& c) {
  const Eigen::Vector3d bc = b.normal.cross(c.normal);
  const double det = a.normal.dot(bc);
  if (!(std::fabs(det) >= 1e-3 * a.normal.norm() * b.normal.norm() * c.normal.norm())) return std::nullopt;
  return Eigen::Vector3d(
      (a.offset * bc + b.offset * c.normal.cross(a.normal) + c.offset * a.normal.cross(b.normal)) / det);
}

std::optional<BoundedPoint> bounded_vertex_point(const ExactPlane& a, const ExactPlane& b,
                                                 const ExactPlane& c) {
  double error = 0.0;
  const Eigen::Vector3d x = cramer(a, b, c, &error);
  if (!std::isfinite(error)) return std::nullopt;
  return BoundedPoint{x, error};
}

}  // namespace morph
