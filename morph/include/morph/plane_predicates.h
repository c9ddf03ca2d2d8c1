// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file plane_predicates.h
/// The generator's exact predicates on planes, with its one tie order. A vertex is three planes; a
/// plane's side at it is the sign of a 4×4 determinant (the planes' normals and offsets) over the
/// 3×3 determinant of the vertex's normals. The doubles of the coefficients are taken as exact
/// rationals: a floating-point filter with an error bound decides almost always, else the same
/// in double-word arithmetic with its bound, else exact integers in the narrowest type that
/// holds them (__int128, Boost.Multiprecision's fixed int256/int512, cpp_int).
///
/// Ties (the plane through the vertex) are settled by symbolic perturbation of the offsets: plane
/// p's offset becomes offset + direction·ε_rank, with ε_r ≫ ε_s whenever rank r < rank s. Stock
/// planes contract (direction -1) and sweeps expand (+1); ranks put the stock first, then the
/// moves in job order (sweep_rank()), so the earlier move owns a shared facet, as in
/// joint_culling.h. The normals are never perturbed, so three planes whose normals are dependent
/// have no vertex (vertex_exists() says so) in the perturbed arrangement either.
///
/// A plane with an exact form (ExactPlane::exact, quantize.h) enters as the rows [n | offset·2^g],
/// integers times powers of two, the offset as two doubles whose sum is exact; the double filter
/// charges the low part to its bound and the integer stage holds both (exact_determinant.h).
#include <morph/quantize.h>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <optional>

namespace morph {

/// A halfspace normal·x <= offset as the exact predicates see it.
struct ExactPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double offset = 0.0;
  /// Position in the tie order: smaller ranks dominate. Distinct planes have distinct ranks.
  std::uint64_t rank = 0;
  /// +1: the perturbation expands the halfspace (sweeps); -1: contracts it (stock).
  int direction = 1;
  /// When set, the plane the predicates decide on (exact on the grid of quantize.h, e.g. a
  /// silhouette plane exactly through both ends of its tool edge); normal and offset are then
  /// its rounded look, used for looks only (vertex_point() also reads the exact form).
  IntegerPlane exact{};
};

/// Rank of a stock plane (stock planes come before every sweep).
constexpr std::uint64_t stock_rank(std::uint32_t plane) {
  return plane;
}
/// Rank of plane `plane` of move `move`'s sweep polytope (its halfspace order).
constexpr std::uint64_t sweep_rank(std::uint32_t move, std::uint32_t plane) {
  return ((std::uint64_t{move} + 1) << 32) | plane;
}

/// Sign of det[a.normal; b.normal; c.normal] (exact): non-zero iff the three planes meet in one
/// point; the sign is the orientation of the triple.
int normals_orientation(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c);

/// True iff the three planes meet in exactly one point.
inline bool vertex_exists(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c) {
  return normals_orientation(a, b, c) != 0;
}

/// The perturbed sign of d.normal·x - d.offset at the vertex x of planes a, b, c: -1 strictly
/// inside d's halfspace, +1 strictly outside; 0 only when d is one of a, b, c (same rank).
/// Independent of the order of a, b, c. Throws std::invalid_argument when the three planes have
/// no vertex (vertex_exists() false).
int side_at_vertex(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c, const ExactPlane& d);

/// The vertex of three planes exact on one grid (ExactPlane::exact) when it is a point of that
/// grid, in grid steps: the three planes' integer values there are zero (checked exactly), so it
/// is their one common point. Nothing when the planes are not all on one grid, have no single
/// common point, or meet between grid points.
std::optional<GridPoint> grid_vertex(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c);

/// grid_vertex() from a point `near` the vertex (a float look at it, well within half a grid
/// step): the grid point nearest `near`, when the three planes' integer values there are zero
/// and their normals independent (checked exactly). Nothing otherwise, also when the vertex is a
/// grid point that `near` is too far from: then side_at_vertex() decides, at more cost.
std::optional<GridPoint> grid_vertex_near(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c,
                                          const Eigen::Vector3d& near);

/// A vertex's grid point, looked for once and kept for every plane asked of the vertex after.
struct VertexGrid {
  std::optional<GridPoint> point;
  bool looked_for = false;
};

/// side_at_vertex(a, b, c, d), through the vertex's grid point (side_at_grid_vertex()) where it is
/// one and d is exact on that grid: `near` a float look at the vertex (grid_vertex_near()),
/// `grid` what was found of it before.
int side_at_vertex_near(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c,
                        const Eigen::Vector3d& near, VertexGrid& grid, const ExactPlane& d);

/// side_at_vertex() at a vertex of a, b, c that is the grid point `x` (grid_vertex()), for d
/// exact on the same grid: d's integer value at x, and where that is zero (the tie of most of a
/// carving's undecided corners: a tool vertex where several facets meet) the perturbation, from
/// the normals' minors alone. The same sign as side_at_vertex(), at a fraction of its cost.
int side_at_grid_vertex(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c, const GridPoint& x,
                        const ExactPlane& d);

/// The unperturbed sign of d.normal·x - d.offset at the vertex x of planes a, b, c (the limit of
/// the arrangement as ε → 0): 0 exactly when d passes through x (always when d is one of a, b,
/// c). Same filter and exact fallback as side_at_vertex(); throws like it.
int limit_side_at_vertex(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c, const ExactPlane& d);

/// limit_side_at_vertex() at a vertex of a, b, c that is the grid point `x` (grid_vertex()): d's
/// integer value there when d is exact on the same grid, else limit_side_at_vertex().
int limit_side_at_grid_vertex(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c,
                              const GridPoint& x, const ExactPlane& d);

/// Three planes held elsewhere, read as a triple without copying them: a vertex's, in a
/// surface's table of planes (conform.h).
struct PlaneTriple {
  std::array<const ExactPlane*, 3> planes{};
  const ExactPlane& operator[](std::size_t i) const { return *planes[i]; }
};
inline PlaneTriple triple_of(const std::array<ExactPlane, 3>& planes) {
  return {{&planes[0], &planes[1], &planes[2]}};
}

/// True iff the vertices u and v (plane triples) are the same exact point in the limit: every
/// plane of v passes exactly through u's point (three independent planes meet in one point).
bool same_limit_point(const PlaneTriple& u, const PlaneTriple& v);
/// The same, given a point near u's vertex (its vertex_point()): where that vertex is a grid
/// point (grid_vertex_near()), v's planes' integer values there decide.
bool same_limit_point(const PlaneTriple& u, const PlaneTriple& v, const Eigen::Vector3d& near_u);

/// The vertex of three planes rounded to doubles: Cramer's rule in long double where its error
/// bound is within 1e-12 of the coordinates' size, otherwise (normals nearly dependent, as a tool
/// facet, its neighbour and the silhouette plane of their common edge) the exact rational, within
/// an ulp. For output, looks and tests, never for decisions. Throws std::invalid_argument when the
/// vertex does not exist.
Eigen::Vector3d vertex_point(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c);

/// Cramer's rule in long double alone: for corners whose normals' determinant is above 1e-7 of the
/// product of their lengths, where it errs by less than about 1e-11·(|offset| + |corner|) (the
/// float looks' margins, RoughCorners). The same point as vertex_point() there.
Eigen::Vector3d conditioned_vertex_point(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c);

/// The vertex of three planes from their float looks (normal, offset) in double, for looks only:
/// x = (o_a·(b×c) + o_b·(c×a) + o_c·(a×b)) / (a·(b×c)). Nothing unless the normals' determinant is
/// at least 1e-3 of the product of their lengths; there it errs by less than 1e-11·|x| (below),
/// as conditioned_vertex_point() does, at a fraction of its cost (it skips the exact forms, the
/// orientation predicate and long double). Each row's offset is at most its normal's length
/// times |x|, so the numerator's rounding is within 18u·|a||b||c|·|x| and the determinant's
/// within 6u·|a||b||c|; over a determinant of at least 1e-3·|a||b||c| that is 2.7e-12·|x|, and
/// the looks' own rounding (2u of each plane, moved by the same conditioning) adds 7e-13·|x|.
std::optional<Eigen::Vector3d> look_vertex_point(const ExactPlane& a, const ExactPlane& b,
                                                 const ExactPlane& c);

/// A vertex rounded to doubles and a bound on its distance from the exact vertex (job units).
struct BoundedPoint {
  Eigen::Vector3d point;
  double error = 0.0;
};
/// vertex_point() (the same point) with a bound on its distance from the exact vertex, from a
/// forward error analysis of its arithmetic that holds however ill-conditioned the three planes
/// are: for filters that must not miss. Nothing when the determinant is too small for the bound
/// to hold. Throws like vertex_point().
std::optional<BoundedPoint> bounded_vertex_point(const ExactPlane& a, const ExactPlane& b,
                                                 const ExactPlane& c);
/// How often the double filter failed and the double-word filter decided (refined), how often
/// both failed and exact integers decided (exact), and how often a tie was settled by the
/// perturbation, in this thread (for the benches).
struct PredicateCounts {
  std::uint64_t calls = 0, exact = 0, ties = 0, refined = 0;
};
PredicateCounts& predicate_counts();

}  // namespace morph
