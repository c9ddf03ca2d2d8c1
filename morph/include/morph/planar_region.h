// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file planar_region.h
/// Planar regions bounded by closed loops of line segments and circular arcs: any number of
/// pieces, each an outer loop (counter-clockwise) with holes (clockwise), so that the region is
/// always on the left of its boundary. Areas and perimeters are exact up to rounding.
#include <morph/planar_curve.h>

#include <cstddef>
#include <string>
#include <vector>

namespace morph::planar {

/// A closed chain: curves[i].end == curves[i + 1].start and the last ends where the first starts.
struct Loop {
  std::vector<Curve> curves;
};

/// One connected piece of a region: an outer loop and the holes directly inside it.
struct Piece {
  std::size_t outer = 0;           ///< index into Region::loops
  std::vector<std::size_t> holes;  ///< indices into Region::loops
};

struct Region {
  std::vector<Loop> loops;
  std::vector<Piece> pieces;
};

/// Signed area enclosed by the loop (positive counter-clockwise), exact for lines and arcs.
double signed_area(const Loop& loop);
/// Sum of the lengths of the loop's curves.
double perimeter(const Loop& loop);
/// Area of the region (outer loops minus holes).
double area(const Region& region);
/// Length of all boundary loops.
double perimeter(const Region& region);
/// Number of holes over all pieces.
std::size_t hole_count(const Region& region);
/// Bounds of every curve.
Box2 bounds(const Region& region);
/// Number of times a ray from p towards +x crosses the loop (half-open rule at vertices).
int crossings(const Loop& loop, const Vec2& p);
/// Crossings of one curve by the ray from p towards +x (the same half-open rule).
int crossings(const Curve& curve, const Vec2& p);
/// True if p is inside the region (even-odd over all loops; p on the boundary is undefined).
bool contains(const Region& region, const Vec2& p);

/// Checks that every loop is closed (gaps up to `gap` are closed by moving the next start onto the
/// previous end), has no zero-length element, and that no two elements cross or overlap except at
/// shared ends. Throws InputError naming `what`, the loop and the element ("stock.json: loop 2,
/// element 5: ..."). The first element of each loop is number 0.
void validate_loops(std::vector<Loop>& loops, const std::string& what, double gap);

/// Orients and nests closed, non-crossing loops: a loop inside an even number of others is an
/// outer loop (made counter-clockwise), inside an odd number a hole (made clockwise); pieces hold
/// each outer loop with the holes nested directly in it. Order: pieces by decreasing area.
Region make_region(std::vector<Loop> loops);
/// Groups loops that are already oriented (outer counter-clockwise, holes clockwise) into pieces:
/// each hole goes to the smallest outer loop containing it. Order: outer loops by decreasing area,
/// then holes by decreasing size.
Region group_pieces(std::vector<Loop> loops);
/// The loop travelled the other way.
Loop reversed(const Loop& loop);

}  // namespace morph::planar
