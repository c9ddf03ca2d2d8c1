// SPDX-License-Identifier: Apache-2.0
// The stress case generators. Each family builds a job whose result is known by construction
// (piece count, and the volume when no pass enters the stock) and that probes one way the
// generator can break: pieces split off or freed, pieces removed whole, self-crossing paths,
// coincident / tangent / overlapping passes, grazing contacts, features at the tolerance, passes
// that never touch the stock, on box, cylinder and mesh stock with sphere and ball-end tools.
//
// Geometry rules that keep the expected counts true and the reference able to see them: every
// gap between cuts and every piece is at least kGapInRadii tool radii (several voxels) wide, and
// no thin ridge is left between passes (partial-depth passes overlap or lie far apart).
#include "campaigns/stress_cases.h"

#include "campaigns/stress_builder.h"

#include <fmt/format.h>
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <morphmill/mesh_io.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

namespace morphmill::stress {

namespace fs = std::filesystem;
using Eigen::Vector3d;

std::uint64_t CaseRandom::next() {
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

double CaseRandom::uniform(double low, double high) {
  return low + (high - low) * static_cast<double>(next() >> 11) * 0x1.0p-53;
}

int CaseRandom::integer(int low, int high) {
  return low + static_cast<int>(next() % static_cast<std::uint64_t>(high - low + 1));
}

bool CaseRandom::chance(double p) {
  return uniform(0.0, 1.0) < p;
}

namespace {

/// Tool and stock height for cuts through the whole stock: a ball-end whose tip runs below the
/// stock, or a sphere centred in a stock thinner than 1.2 radii (so it cuts both faces).
struct FullDepth {
  bool sphere = false;
  double radius = 0, height = 0, tool_z = 0;
  double half_width_at_faces = 0;  ///< half width of a slot where it meets the top and bottom faces
};

FullDepth draw_full_depth(CaseRandom& rng) {
  FullDepth f;
  f.sphere = rng.chance(0.4);
  f.radius = round3(rng.uniform(1.5, 3.0));
  if (f.sphere) {
    // The slot's walls meet the faces at 60 degrees or more.
    f.height = round3(f.radius * rng.uniform(0.5, 1.0));
    f.tool_z = f.height / 2;
    f.half_width_at_faces = std::sqrt(f.radius * f.radius - f.height * f.height / 4);
  } else {
    f.height = round3(rng.uniform(3.0, 8.0));
    // The whole hemisphere below the stock: vertical walls through the full height.
    f.tool_z = -f.radius - round3(rng.uniform(0.2, 1.0));
    f.half_width_at_faces = f.radius;
  }
  return f;
}

/// Slot centres along one axis, from `start`, each slot 2r wide and separated by >= gap.
std::vector<double> slot_positions(CaseRandom& rng, int count, double radius, double start, double* end) {
  std::vector<double> centres;
  double x = start;
  for (int i = 0; i < count; ++i) {
    x += radius + radius * rng.uniform(kGapInRadii, kGapInRadii + 1.0);
    x = round3(x);
    centres.push_back(x);
    x += radius;
  }
  *end = round3(x + radius * rng.uniform(kGapInRadii, kGapInRadii + 1.0));
  return centres;
}

/// Straight passes along y at the given x centres, from y0 to y1, joined into one zigzag path
/// (joins outside the stock) or given as separate paths.
/// Straight passes at the given positions from `from` to `to` along y (or along x), alternating
/// direction; as one zigzag path or as separate paths.
void slots_along(Builder& b, bool along_y, const std::vector<double>& positions, double from, double to,
                 double z, bool one_path) {
  auto point = [&](double position, double along) {
    return along_y ? Vector3d(position, along, z) : Vector3d(along, position, z);
  };
  std::vector<Vector3d> zigzag;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const bool forward = i % 2 == 0;
    const Vector3d p = point(positions[i], forward ? from : to), q = point(positions[i], forward ? to : from);
    if (one_path) {
      zigzag.push_back(p);
      zigzag.push_back(q);
    } else {
      b.path({p, q});
    }
  }
  if (one_path) b.path(zigzag);
}

void slots_along_y(Builder& b, const std::vector<double>& xs, double y0, double y1, double z, bool one_path) {
  slots_along(b, true, xs, y0, y1, z, one_path);
}

void slots_along_x(Builder& b, const std::vector<double>& ys, double x0, double x1, double z, bool one_path) {
  slots_along(b, false, ys, x0, x1, z, one_path);
}

const char* tool_word(bool sphere) {
  return sphere ? "sphere" : "ballend";
}

// --- families ------------------------------------------------------------------------------

// k full-depth parallel slots: box -> k + 1 pieces; cylinder (chords inside the disc) -> k + 1.
void through_slots(CaseRandom& rng, Builder& b) {
  const FullDepth f = draw_full_depth(rng);
  b.tool(f.sphere, f.radius, f.height + 10);
  const int k = rng.integer(1, 3);
  const int stock_kind = rng.integer(0, 4);  // 0-2 box, 3 cylinder, 4 box as mesh
  b.swap_xy(rng.chance(0.5));
  double length = 0;
  const auto xs = slot_positions(rng, k, f.radius, 0.0, &length);
  const double width = round3(rng.uniform(8.0, 20.0));
  const double over = f.radius + round3(rng.uniform(0.5, 2.0));
  std::string stock;
  if (stock_kind == 3) {
    // The slots are chords: centre the layout on the axis with the disc reaching past both ends.
    const double radius = round3(length / 2 + rng.uniform(0.0, f.radius));
    std::vector<double> centred;
    for (double x : xs) centred.push_back(x - length / 2);
    b.cylinder(0, 0, radius, f.height);
    slots_along_y(b, centred, -radius - over, radius + over, f.tool_z, rng.chance(0.5));
    stock = "cylinder";
  } else {
    const Vector3d lo(0, 0, 0), hi(length, width, f.height);
    if (stock_kind == 4) {
      b.box_as_mesh(lo, hi);
      stock = "mesh box";
    } else {
      b.box(lo, hi);
      stock = "box";
    }
    slots_along_y(b, xs, -over, width + over, f.tool_z, rng.chance(0.5));
  }
  b.finish(fmt::format("{}, {}, {} full-depth slot(s)", stock, tool_word(f.sphere), k), k + 1);
}

// a x b full-depth slots crossing at right angles: (a + 1)(b + 1) pieces.
void crossing_slots(CaseRandom& rng, Builder& b) {
  const FullDepth f = draw_full_depth(rng);
  b.tool(f.sphere, f.radius, f.height + 10);
  const int a = rng.integer(1, 2), c = rng.integer(1, 2);
  double length = 0, width = 0;
  const auto xs = slot_positions(rng, a, f.radius, 0.0, &length);
  const auto ys = slot_positions(rng, c, f.radius, 0.0, &width);
  const double over = f.radius + round3(rng.uniform(0.5, 2.0));
  const bool as_mesh = rng.chance(0.3);
  const Vector3d lo(0, 0, 0), hi(length, width, f.height);
  if (as_mesh)
    b.box_as_mesh(lo, hi);
  else
    b.box(lo, hi);
  const bool one_path = rng.chance(0.5);
  if (rng.chance(0.5)) {
    slots_along_y(b, xs, -over, width + over, f.tool_z, one_path);
    slots_along_x(b, ys, -over, length + over, f.tool_z, one_path);
  } else {
    slots_along_x(b, ys, -over, length + over, f.tool_z, one_path);
    slots_along_y(b, xs, -over, width + over, f.tool_z, one_path);
  }
  b.finish(fmt::format("{}, {}, {} x {} crossing full-depth slots", as_mesh ? "mesh box" : "box",
                       tool_word(f.sphere), a, c),
           (a + 1) * (c + 1));
}

// A closed contour cut full depth frees the island inside it: square ring -> 2 pieces, two
// nested rings -> 3, a polygonal "circle" ring -> 2, a ring crossed by a through slot -> 4.
void island_ring(CaseRandom& rng, Builder& b) {
  const FullDepth f = draw_full_depth(rng);
  b.tool(f.sphere, f.radius, f.height + 10);
  const double r = f.radius, gap = kGapInRadii * r;
  const int variant = rng.integer(0, 3);
  // Half size of the (outer) ring's path, measured from the stock centre.
  const double island =
      round3(r * rng.uniform(kGapInRadii, kGapInRadii + 1.0));  // innermost island half size
  double ring = island + r;
  double inner_ring = 0;
  if (variant == 1) {
    inner_ring = ring;
    ring = round3(inner_ring + 2 * r + gap * rng.uniform(1.0, 1.5));
  }
  if (variant == 3) ring = round3(std::max(ring, 2 * r + gap * 1.2));  // room for the slot through the island
  const double frame = round3(gap * rng.uniform(1.0, 2.0));
  const bool cylinder = variant != 2 && rng.chance(0.3);
  const double cx = round3(rng.uniform(-5, 5)), cy = round3(rng.uniform(-5, 5));
  double half = ring + r + frame;  // box half size (or cylinder radius)
  if (cylinder) {
    half = round3(ring * std::sqrt(2.0) + r + frame);
    b.cylinder(cx, cy, half, f.height);
  } else {
    b.box(Vector3d(cx - half, cy - half, 0), Vector3d(cx + half, cy + half, f.height));
  }
  auto square = [&](double h) {
    const double z = f.tool_z;
    const int start = rng.integer(0, 3);  // where the closed contour starts and ends
    const Vector3d corners[4] = {
        {cx - h, cy - h, z}, {cx + h, cy - h, z}, {cx + h, cy + h, z}, {cx - h, cy + h, z}};
    std::vector<Vector3d> loop;
    for (int i = 0; i <= 4; ++i) loop.push_back(corners[(start + i) % 4]);
    if (rng.chance(0.5)) std::reverse(loop.begin(), loop.end());
    b.path(loop);
  };
  std::string what;
  int pieces = 2;
  switch (variant) {
    case 0:
      square(ring);
      what = "square ring";
      break;
    case 1:
      square(ring);
      square(inner_ring);
      what = "two nested square rings";
      pieces = 3;
      break;
    case 2: {
      // A regular polygon whose inscribed circle keeps the island and frame as wide as above.
      const int sides = rng.integer(8, 16);
      const double circumradius = ring / std::cos(M_PI / sides);
      const double phase = rng.uniform(0, 2 * M_PI);
      std::vector<Vector3d> loop;
      for (int i = 0; i <= sides; ++i) {
        const double angle = phase + 2 * M_PI * i / sides;
        loop.emplace_back(cx + circumradius * std::cos(angle), cy + circumradius * std::sin(angle), f.tool_z);
      }
      b.path(loop);
      what = fmt::format("{}-gon ring", sides);
      break;
    }
    default: {
      square(ring);
      const double over = r + 1.0;
      b.path({Vector3d(cx, cy - half - over, f.tool_z), Vector3d(cx, cy + half + over, f.tool_z)});
      what = "square ring crossed by a through slot";
      pieces = 4;
    }
  }
  b.finish(fmt::format("{}, {}, {}", cylinder ? "cylinder" : "box", tool_word(f.sphere), what), pieces);
}

// Through slots split a bar into pieces and a zigzag pocket removes one of them whole.
void removed_piece(CaseRandom& rng, Builder& b) {
  const FullDepth f = draw_full_depth(rng);
  b.tool(f.sphere, f.radius, f.height + 10);
  const double r = f.radius;
  // Passes closer than twice the slot's narrowest half width leave nothing between them.
  const double step = round3(1.2 * f.half_width_at_faces);
  const double width = round3(rng.uniform(8.0, 16.0));
  const double over = r + round3(rng.uniform(0.5, 2.0));
  const bool interior = rng.chance(0.5);  // remove a piece between two slots, or the end piece
  const double piece = round3(r * rng.uniform(1.0, 3.0));
  std::vector<double> slots;
  double removed_from = 0, removed_to = 0, x = 0;
  if (interior) {
    x = round3(r + kGapInRadii * r * rng.uniform(1.0, 1.5));  // first slot: a kept piece before it
    slots.push_back(x);
    removed_from = x + r;
    removed_to = removed_from + piece;
    x = removed_to + r;
    slots.push_back(x);
  } else {
    removed_to = piece;
    x = piece + r;
    slots.push_back(x);
  }
  const int extra = rng.integer(0, 1);
  double length = 0;
  const auto more = slot_positions(rng, extra, r, x + r, &length);
  slots.insert(slots.end(), more.begin(), more.end());
  b.box(Vector3d(0, 0, 0), Vector3d(length, width, f.height));
  slots_along_y(b, slots, -over, width + over, f.tool_z, rng.chance(0.5));
  // Pocket passes from the removed piece's start until they overlap the next slot's cut at the
  // faces, where a sphere's cut is narrowest (reaching only the piece's end would leave a strip
  // r - half width thick at each face).
  std::vector<double> pocket;
  const double next_slot = removed_to + r;
  for (double p = removed_from;; p += step) {
    pocket.push_back(p);
    if (p + f.half_width_at_faces >= next_slot - f.half_width_at_faces) break;
  }
  slots_along_y(b, pocket, -over, width + over, f.tool_z, true);
  const int pieces = (interior ? 2 : 1) + extra;
  b.finish(fmt::format("box, {}, {} piece removed by a {}-pass pocket, {} slot(s)", tool_word(f.sphere),
                       interior ? "interior" : "end", pocket.size(), slots.size()),
           pieces);
}

/// A stock with a flat top at z = top for the partial-depth families: box or vertical cylinder.
struct TopFace {
  double top = 0;
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;  ///< a rectangle on the top face (inside the cylinder's disc)
  std::string name;
};

TopFace partial_depth_stock(CaseRandom& rng, Builder& b, bool allow_cylinder) {
  TopFace t;
  t.top = round3(rng.uniform(6.0, 10.0));  // partial cuts reach at most 4.2 deep
  if (allow_cylinder && rng.chance(0.35)) {
    const double radius = round3(rng.uniform(10.0, 16.0));
    b.cylinder(0, 0, radius, t.top);
    const double h = radius / std::sqrt(2.0);
    t.x0 = t.y0 = -h;
    t.x1 = t.y1 = h;
    t.name = "cylinder";
  } else {
    const double length = round3(rng.uniform(16.0, 30.0)), width = round3(rng.uniform(12.0, 24.0));
    b.box(Vector3d(0, 0, 0), Vector3d(length, width, t.top));
    t.x1 = length;
    t.y1 = width;
    t.name = "box";
  }
  return t;
}

void partial_tool(CaseRandom& rng, Builder& b, double top) {
  const bool sphere = rng.chance(0.5);
  b.tool(sphere, round3(rng.uniform(1.5, 3.0)), top + 10);
}

/// Depth of a partial cut and the width it leaves on the top face (both tools: the cut stays
/// within the tool's spherical tip).
struct PartialCut {
  double depth = 0, top_width = 0, tool_z = 0;
};

PartialCut draw_partial_cut(CaseRandom& rng, const Builder& b, double top) {
  PartialCut c;
  const double r = b.radius();
  // At least 0.7 r deep, so the cut's walls meet the top face at 60 degrees or more.
  c.depth = round3(r * rng.uniform(0.7, 1.4));
  c.top_width = c.depth >= r ? 2 * r : 2 * std::sqrt(2 * r * c.depth - c.depth * c.depth);
  c.tool_z = b.tool_z_for_lowest(top - c.depth);
  return c;
}

/// Step between neighbouring partial-depth passes: they overlap on the top face, so no ridge
/// thinner than the cut is left standing between them.
double overlapping_step(CaseRandom& rng, const PartialCut& cut) {
  return round3(cut.top_width * rng.uniform(0.3, 0.55));
}

// Spirals that cross themselves, at partial depth: one piece.
void spiral(CaseRandom& rng, Builder& b) {
  const TopFace t = partial_depth_stock(rng, b, true);
  partial_tool(rng, b, t.top);
  const PartialCut cut = draw_partial_cut(rng, b, t.top);
  const double step = overlapping_step(rng, cut);
  const double cx = (t.x0 + t.x1) / 2, cy = (t.y0 + t.y1) / 2;
  const double reach = std::min(t.x1 - t.x0, t.y1 - t.y0) / 2 * rng.uniform(0.6, 1.2);
  std::vector<Vector3d> points;
  const bool square = rng.chance(0.4);
  if (square) {
    // Square spiral: legs growing by one step every half turn.
    Vector3d p(cx, cy, cut.tool_z);
    points.push_back(p);
    const Vector3d directions[4] = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
    for (int leg = 0; (leg / 2 + 1) * step < 2 * reach && leg < 16; ++leg) {
      p += directions[leg % 4] * ((leg / 2 + 1) * step);
      points.push_back(p);
    }
  } else {
    const int per_turn = rng.integer(8, 14);
    const double start_angle = rng.uniform(0, 2 * M_PI);
    const double turns = std::min(reach / step, 3.0);
    const int count = std::max(4, static_cast<int>(turns * per_turn));
    for (int i = 0; i <= count; ++i) {
      const double angle = 2 * M_PI * i / per_turn;
      const double rho = step * 0.5 + step * angle / (2 * M_PI);
      points.emplace_back(cx + rho * std::cos(start_angle + angle), cy + rho * std::sin(start_angle + angle),
                          cut.tool_z);
    }
  }
  // Back across the centre: crosses every turn.
  const Vector3d last = points.back();
  points.emplace_back(2 * cx - last.x(), 2 * cy - last.y(), cut.tool_z);
  if (rng.chance(0.3)) std::reverse(points.begin(), points.end());
  b.path(points);
  b.finish(fmt::format("{}, {}, {} spiral of {} moves crossing itself, depth {}", t.name,
                       tool_word(b.sphere()), square ? "square" : "round", points.size() - 1, cut.depth),
           1);
}

// Zigzags crossing each other, or a star polygon crossing itself, at partial depth: one piece.
void zigzag_cross(CaseRandom& rng, Builder& b) {
  const TopFace t = partial_depth_stock(rng, b, true);
  partial_tool(rng, b, t.top);
  const PartialCut cut = draw_partial_cut(rng, b, t.top);
  const double cx = (t.x0 + t.x1) / 2, cy = (t.y0 + t.y1) / 2;
  const double half = std::min(t.x1 - t.x0, t.y1 - t.y0) / 2 * rng.uniform(0.3, 0.5);
  std::string what;
  if (rng.chance(0.6)) {
    const double step = overlapping_step(rng, cut);
    const int passes = std::max(2, std::min(7, static_cast<int>(2 * half / step) + 1));
    std::vector<double> xs, ys;
    for (int i = 0; i < passes; ++i) {
      xs.push_back(cx - half + i * step);
      ys.push_back(cy - half + i * step);
    }
    slots_along_y(b, xs, cy - half, cy + half, cut.tool_z, true);
    slots_along_x(b, ys, cx - half, cx + half, cut.tool_z, true);
    what = fmt::format("two crossing zigzags of {} passes", passes);
  } else {
    static const int stars[][2] = {{5, 2}, {7, 2}, {7, 3}, {8, 3}};
    const auto& star = stars[rng.integer(0, 3)];
    const double phase = rng.uniform(0, 2 * M_PI);
    std::vector<Vector3d> points;
    for (int i = 0; i <= star[0]; ++i) {
      const double angle = phase + 2 * M_PI * star[1] * i / star[0];
      points.emplace_back(cx + half * std::cos(angle), cy + half * std::sin(angle), cut.tool_z);
    }
    b.path(points);
    what = fmt::format("star polygon {{{}/{}}}", star[0], star[1]);
  }
  b.finish(fmt::format("{}, {}, {}, depth {}", t.name, tool_word(b.sphere()), what, cut.depth), 1);
}

// The same pass repeated: identical, reversed, split into collinear moves. Partial depth -> 1
// piece; full depth through a box -> 2.
void coincident(CaseRandom& rng, Builder& b) {
  b.tolerance(draw_tolerance(rng));
  const bool full = rng.chance(0.4);
  Vector3d a, c;
  std::string where;
  if (full) {
    const FullDepth f = draw_full_depth(rng);
    b.tool(f.sphere, f.radius, f.height + 10);
    double length = 0;
    const auto xs = slot_positions(rng, 1, f.radius, 0.0, &length);
    const double width = round3(rng.uniform(8.0, 16.0)), over = f.radius + 1.0;
    b.box(Vector3d(0, 0, 0), Vector3d(length, width, f.height));
    a = Vector3d(xs[0], -over, f.tool_z);
    c = Vector3d(xs[0], width + over, f.tool_z);
    where = "box, full depth";
  } else {
    const TopFace t = partial_depth_stock(rng, b, true);
    partial_tool(rng, b, t.top);
    const PartialCut cut = draw_partial_cut(rng, b, t.top);
    const double y = round3(rng.uniform(t.y0 + (t.y1 - t.y0) * 0.3, t.y1 - (t.y1 - t.y0) * 0.3));
    // Ends inside or outside the stock.
    a = Vector3d(t.x0 + (rng.chance(0.5) ? -3.0 : 2.0), y, cut.tool_z);
    c = Vector3d(t.x1 + (rng.chance(0.5) ? 3.0 : -2.0), y, cut.tool_z);
    where = t.name + ", partial depth";
  }
  const Vector3d middle = a + (c - a) * round3(rng.uniform(0.2, 0.8));
  const int repeats = rng.integer(2, 3);
  std::vector<std::string> kinds;
  for (int i = 0; i < repeats; ++i) {
    switch (rng.integer(0, 2)) {
      case 0:
        b.path({a, c});
        kinds.push_back("same");
        break;
      case 1:
        b.path({c, a});
        kinds.push_back("reversed");
        break;
      default:
        b.path({a, middle, c});
        kinds.push_back("split");
    }
  }
  if (rng.chance(0.4)) {
    b.path({a, c, a});  // there and back in one path: a 180 degree turn onto itself
    kinds.push_back("there-and-back");
  }
  std::string list;
  for (const auto& k : kinds) list += (list.empty() ? "" : "+") + k;
  b.finish(fmt::format("{}, {}, coincident passes {}", where, tool_word(b.sphere()), list), full ? 2 : 1);
}

// Parallel passes overlapping by random amounts, at different partial depths (1 piece), or an
// overlapping pair through a box (it acts as one wide slot: 2 pieces).
void overlap(CaseRandom& rng, Builder& b) {
  b.tolerance(draw_tolerance(rng));
  if (rng.chance(0.4)) {
    const FullDepth f = draw_full_depth(rng);
    b.tool(f.sphere, f.radius, f.height + 10);
    double length = 0;
    const auto xs = slot_positions(rng, 1, f.radius, 0.0, &length);
    // A shift below twice the narrowest half width keeps the pair one slot at both faces.
    const double shift = round3(f.half_width_at_faces * rng.uniform(0.1, 1.8));
    length += shift;
    const double width = round3(rng.uniform(8.0, 16.0)), over = f.radius + 1.0;
    b.box(Vector3d(0, 0, 0), Vector3d(length, width, f.height));
    slots_along_y(b, {xs[0], xs[0] + shift}, -over, width + over, f.tool_z, rng.chance(0.5));
    b.finish(fmt::format("box, {}, full-depth pair overlapping by shift {}", tool_word(f.sphere), shift), 2);
    return;
  }
  const TopFace t = partial_depth_stock(rng, b, true);
  partial_tool(rng, b, t.top);
  const int drawn = rng.integer(2, 4);
  int passes = 0;
  double y = (t.y0 + t.y1) / 2 - b.radius();
  for (int i = 0; i < drawn; ++i) {
    // A tool reaching past the top face's side cuts that side below the top (a sphere's centre
    // lies below it) and slices a wedge off along the whole pass: 2 pieces, not 1 (seed 59, case
    // 133 of version 1).
    if (i > 0 && y + b.radius() >= t.y1 - 0.1) break;
    ++passes;
    const PartialCut cut = draw_partial_cut(rng, b, t.top);
    const double x0 = t.x0 - 2.0, x1 = t.x1 + 2.0;
    if (rng.chance(0.5))
      b.path({Vector3d(x0, y, cut.tool_z), Vector3d(x1, y, cut.tool_z)});
    else
      b.path({Vector3d(x1, y, cut.tool_z), Vector3d(x0, y, cut.tool_z)});
    y += overlapping_step(rng, cut) * 0.9;
  }
  b.finish(
      fmt::format("{}, {}, {} overlapping passes at different depths", t.name, tool_word(b.sphere()), passes),
      1);
}

// Tangent contacts that must not leave material: two ball-end slots through a box exactly two
// radii apart (their walls touch: one wide slot); a pass continued by collinear moves; a second
// pass higher on the same line (ball-end: the walls coincide); a polygon arc leaving a line.
void tangent(CaseRandom& rng, Builder& b) {
  b.tolerance(draw_tolerance(rng));
  if (rng.chance(0.5)) {
    const double r = round3(rng.uniform(1.5, 3.0)), height = round3(rng.uniform(3.0, 8.0));
    b.tool(false, r, height + 10);
    const double z = -r - 0.5;  // vertical walls through the full height
    double length = 0;
    const int separate = rng.integer(0, 1);
    auto xs = slot_positions(rng, 1 + separate, r, 0.0, &length);
    const double twin = xs[0] + 2 * r;  // tangent to the first slot
    for (double& x : xs)
      if (x > xs[0]) x += 2 * r;
    length += 2 * r;
    const double width = round3(rng.uniform(8.0, 16.0)), over = r + 1.0;
    b.box(Vector3d(0, 0, 0), Vector3d(length, width, height));
    std::vector<double> all = xs;
    all.insert(all.begin() + 1, twin);
    slots_along_y(b, all, -over, width + over, z, rng.chance(0.5));
    b.finish(fmt::format("box, ballend, two full-depth slots exactly 2r apart{}",
                         separate ? " + one more slot" : ""),
             2 + separate);
    return;
  }
  const TopFace t = partial_depth_stock(rng, b, true);
  partial_tool(rng, b, t.top);
  const PartialCut cut = draw_partial_cut(rng, b, t.top);
  const double y = (t.y0 + t.y1) / 2, x0 = t.x0 - 2.0, x1 = t.x1 + 2.0;
  std::vector<Vector3d> line;
  const int pieces = rng.integer(2, 5);
  for (int i = 0; i <= pieces; ++i) line.emplace_back(x0 + (x1 - x0) * i / pieces, y, cut.tool_z);
  std::string what = fmt::format("a pass split into {} collinear moves", pieces);
  if (rng.chance(0.5)) {
    // Leave the line along a polygonal quarter circle whose first chord is tangent to it.
    const double bend = (t.y1 - t.y0) * 0.3;
    const Vector3d end = line.back();
    line.pop_back();
    const Vector3d start = line.back();
    const int chords = rng.integer(4, 8);
    for (int i = 1; i <= chords; ++i) {
      const double angle = M_PI / 2 * i / chords;
      line.emplace_back(start.x() + bend * std::sin(angle), y + bend * (1 - std::cos(angle)), cut.tool_z);
    }
    (void)end;
    what += " turning tangentially into a polygonal arc";
  }
  b.path(line);
  if (!b.sphere()) {
    const double higher = round3(cut.depth * rng.uniform(0.2, 0.8));
    b.path({Vector3d(x1, y, cut.tool_z + higher), Vector3d(x0, y, cut.tool_z + higher)});
    what += " and the same line higher (coincident walls)";
  }
  b.finish(fmt::format("{}, {}, {}", t.name, tool_word(b.sphere()), what), 1);
}

/// Offset from touching for a grazing pass: exactly touching, tolerance/2 clear of the stock, or
/// tolerance/2 into it.
double graze_offset(CaseRandom& rng, double tolerance, std::string* word) {
  switch (rng.integer(0, 2)) {
    case 0:
      *word = "exactly touching";
      return 0.0;
    case 1:
      *word = "tolerance/2 clear";
      return tolerance / 2;
    default:
      *word = "tolerance/2 deep";
      return -tolerance / 2;
  }
}

// Passes grazing a face: the top face, a side face of a box, the side of a cylinder.
void graze_face(CaseRandom& rng, Builder& b) {
  const double tolerance = draw_tolerance(rng);
  b.tolerance(tolerance);
  const TopFace t = partial_depth_stock(rng, b, true);
  partial_tool(rng, b, t.top);
  const double r = b.radius();
  std::string offset_word;
  const double offset = graze_offset(rng, tolerance, &offset_word);
  const int where = rng.integer(0, 1);
  std::string what;
  if (where == 0 || t.name == "box") {
    if (where == 0) {
      const double z = b.tool_z_for_lowest(t.top + offset);
      const double y = round3(rng.uniform(t.y0 + 3, t.y1 - 3));
      b.path({Vector3d(t.x0 - 3, y, z), Vector3d(t.x1 + 3, y, z)});
      what = "along the top face";
    } else {
      // Beside the box's front face y = 0, the tool's side at distance `offset` from it.
      const double z = b.tool_z_for_lowest(round3(rng.uniform(0.2, 0.5) * t.top));
      const double y = -r - offset;
      b.path({Vector3d(t.x0 - 3, y, z), Vector3d(t.x1 + 3, y, z)});
      what = "along the front face";
    }
  } else {
    // Beside the cylinder: a vertical pass whose tool side touches the side wall along a line.
    const double radius = t.x1 * std::sqrt(2.0);
    const double angle = rng.uniform(0, 2 * M_PI), rho = radius + r + offset;
    const double x = rho * std::cos(angle), y = rho * std::sin(angle);
    if (b.sphere())
      b.path({Vector3d(x, y, -2), Vector3d(x, y, t.top + 2)});
    else
      b.path({Vector3d(x, y, t.top * 0.3), Vector3d(x, y, t.top * 0.7)});
    what = "beside the cylinder wall";
  }
  if (offset >= 0) b.expected_volume(b.stock_volume());
  b.finish(fmt::format("{}, {}, {}, {}", t.name, tool_word(b.sphere()), what, offset_word), 1);
}

// Passes along an edge of a box: centred on it (a rounded groove), or touching it from the
// outside diagonal exactly / tolerance/2 clear / tolerance/2 deep.
void graze_edge(CaseRandom& rng, Builder& b) {
  const double tolerance = draw_tolerance(rng);
  b.tolerance(tolerance);
  const double length = round3(rng.uniform(16, 30)), width = round3(rng.uniform(12, 24)),
               top = round3(rng.uniform(5, 10));
  b.box(Vector3d(0, 0, 0), Vector3d(length, width, top));
  const bool sphere = rng.chance(0.5);
  const double r = round3(rng.uniform(1.5, 3.0));
  b.tool(sphere, r, top + 10);
  std::string word;
  double c =
      0;  // hemisphere / sphere centre at (y, z) = (-c, top + c): diagonal distance sqrt(2) c to the edge
  if (rng.chance(0.25)) {
    word = "centred on the edge";
    c = 0;
  } else {
    const double offset = graze_offset(rng, tolerance, &word);
    c = (r + offset) / std::sqrt(2.0);
    if (offset >= 0) b.expected_volume(b.stock_volume());
  }
  const double centre_z = top + c;
  const double tool_z = sphere ? centre_z : centre_z - r;
  b.path({Vector3d(-3, -c, tool_z), Vector3d(length + 3, -c, tool_z)});
  b.finish(fmt::format("box, {}, along the top front edge, {}", tool_word(sphere), word), 1);
}

// Features at the tolerance: cuts as deep as 0.5-3 tolerances, two passes a third of a
// tolerance apart, a pass sinking by one tolerance along its length.
void near_tolerance(CaseRandom& rng, Builder& b) {
  const double tolerance = draw_tolerance(rng);
  b.tolerance(tolerance);
  const TopFace t = partial_depth_stock(rng, b, true);
  partial_tool(rng, b, t.top);
  static const double factors[] = {0.5, 1.0, 1.5, 3.0};
  const double depth = tolerance * factors[rng.integer(0, 3)];
  const double z = b.tool_z_for_lowest(t.top - depth);
  const double y = round3(rng.uniform(t.y0 + 3, t.y1 - 3));
  std::string what;
  switch (rng.integer(0, 2)) {
    case 0:
      b.path({Vector3d(t.x0 - 3, y, z), Vector3d(t.x1 + 3, y, z)});
      what = fmt::format("a cut {} deep", depth);
      break;
    case 1:
      b.path({Vector3d(t.x0 - 3, y, z), Vector3d(t.x1 + 3, y, z)});
      b.path({Vector3d(t.x1 + 3, y + tolerance / 3, z), Vector3d(t.x0 - 3, y + tolerance / 3, z)});
      what = fmt::format("two cuts {} deep, tolerance/3 apart", depth);
      break;
    default:
      b.path({Vector3d(t.x0 - 3, y, z + tolerance), Vector3d(t.x1 + 3, y, z - tolerance)});
      what = fmt::format("a cut sinking from {} to {} deep", depth - tolerance, depth + tolerance);
  }
  b.finish(fmt::format("{}, {}, {}", t.name, tool_word(b.sphere()), what), 1);
}

// Passes that never reach the stock (result = stock): above it, beside it, and inside its
// bounding box but outside the stock (cylinder corners, octahedron faces).
void outside(CaseRandom& rng, Builder& b) {
  b.tolerance(draw_tolerance(rng));
  const int kind = rng.integer(0, 3);  // box, cylinder, octahedron mesh, box mesh
  const bool sphere = kind == 0 || rng.chance(0.7);
  const double r = round3(rng.uniform(1.5, 3.0));
  const double margin = round3(rng.uniform(0.2, 1.0));
  std::vector<std::vector<Vector3d>> passes;
  std::string name;
  double top = 0;
  if (kind == 0 || kind == 3) {
    const double length = round3(rng.uniform(12, 24)), width = round3(rng.uniform(10, 20));
    top = round3(rng.uniform(4, 10));
    if (kind == 0) {
      b.box(Vector3d(0, 0, 0), Vector3d(length, width, top));
      name = "box";
    } else {
      b.box_as_mesh(Vector3d(0, 0, 0), Vector3d(length, width, top));
      name = "mesh box";
    }
    const double side = r + margin;
    passes.push_back({Vector3d(-5, -side, top / 2), Vector3d(length + 5, -side, top / 2)});  // beside
    passes.push_back({Vector3d(length + side, -5, top * 0.3), Vector3d(length + side, width + 5, top * 0.7)});
    // Diagonal past a vertical edge, at distance `side` from it.
    const Vector3d corner(length, width, 0);
    const Vector3d away = Vector3d(1, 1, 0).normalized() * side, along = Vector3d(1, -1, 0).normalized() * 6;
    passes.push_back(
        {corner + away - along + Vector3d(0, 0, top / 2), corner + away + along + Vector3d(0, 0, top / 2)});
  } else if (kind == 1) {
    const double radius = round3(rng.uniform(8, 14));
    top = round3(rng.uniform(5, 12));
    b.cylinder(0, 0, radius, top);
    name = "cylinder";
    // In the bounding box's corners: at 45 degrees, distance radius + r + margin from the axis.
    const double rho = radius + r + margin;
    for (int q = 0; q < 4; ++q) {
      const double angle = M_PI / 4 + q * M_PI / 2;
      const Vector3d foot(rho * std::cos(angle), rho * std::sin(angle), top / 2);
      const Vector3d along(-std::sin(angle), std::cos(angle), 0);
      passes.push_back({foot - along * 2.0, foot + along * 2.0});
    }
  } else {
    const double a = round3(rng.uniform(6, 10));
    const Vector3d centre(round3(rng.uniform(-3, 3)), round3(rng.uniform(-3, 3)), a);
    b.mesh_stock(octahedron_mesh(centre, a), "octahedron");
    top = 2 * a;
    name = "octahedron mesh";
    // Beside a face, `r + margin` out along its normal, running parallel to it.
    for (int i = 0; i < 3; ++i) {
      const Vector3d signs(rng.chance(0.5) ? 1 : -1, rng.chance(0.5) ? 1 : -1, rng.chance(0.5) ? 1 : -1);
      const Vector3d normal = signs.normalized();
      const Vector3d face_centre = centre + signs * (a / 3);
      const Vector3d along = normal.cross(Vector3d(signs.x(), -signs.y(), 0)).normalized() * (a / 3);
      const Vector3d foot = face_centre + normal * (r + margin);
      passes.push_back({foot - along, foot + along});
    }
  }
  b.tool(sphere, r, 2 * top + 20);
  const int count = rng.integer(1, static_cast<int>(passes.size()));
  for (int i = 0; i < count; ++i) {
    auto pass = passes[i];
    if (!sphere) {
      // A ball-end's body reaches up: keep it entirely above the stock instead.
      for (auto& p : pass) p.z() = top + margin;
    }
    b.path(pass);
  }
  if (rng.chance(0.5)) {
    // And one high above the stock.
    const double z = b.tool_z_for_lowest(top + margin + 1);
    b.path({Vector3d(-5, -5, z), Vector3d(30, 30, z)});
  }
  b.expected_volume(b.stock_volume());
  b.finish(
      fmt::format("{}, {}, {} pass(es) outside the stock, {} clear", name, tool_word(sphere), count, margin),
      1);
}

// An octahedron mesh cut through its waist by a zigzag: sphere -> top and bottom pieces; the
// ball-end's body also takes the whole top -> 1 piece. Or its apex cut off -> 1 piece.
void mesh_split(CaseRandom& rng, Builder& b) {
  b.tolerance(draw_tolerance(rng));
  const double a = round3(rng.uniform(7, 11));
  const Vector3d centre(round3(rng.uniform(-3, 3)), round3(rng.uniform(-3, 3)), a);
  b.mesh_stock(octahedron_mesh(centre, a), "octahedron");
  const bool sphere = rng.chance(0.6);
  const double r = round3(rng.uniform(1.5, 2.5));
  b.tool(sphere, r, 3 * a);
  if (rng.chance(0.3)) {
    // A sphere deeper than 2r would tunnel under the apex and, up to about (1 + sqrt(2)) r, cut
    // its tip loose (2 pieces): stay shallower than 1.8 r so the apex is shaved off (1 piece).
    // A ball-end's body takes everything above its tip.
    const double depth = sphere ? round3(r * rng.uniform(0.5, 1.8)) : round3(rng.uniform(0.3, 0.6) * a);
    const double z = b.tool_z_for_lowest(centre.z() + a - depth);
    b.path({Vector3d(centre.x() - a, centre.y() + round3(rng.uniform(-1, 1)), z),
            Vector3d(centre.x() + a, centre.y() + round3(rng.uniform(-1, 1)), z)});
    b.finish(fmt::format("octahedron mesh, {}, apex cut {} deep", tool_word(sphere), depth), 1);
    return;
  }
  const double z = b.tool_z_for_lowest(centre.z() - r * 0.3);
  // Passes along x at y from -a to a; their ends stay sqrt(3) r + 1 outside the faces.
  // Tight steps keep the cusps between passes blunt where they run into the sloped faces.
  const double step = round3(r * rng.uniform(0.6, 1.0));
  const double reach = a + std::sqrt(3.0) * r + 1;
  std::vector<double> ys;
  for (double y = -a + 0.5 * r;; y += step) {
    ys.push_back(centre.y() + y);
    if (y + 0.5 * r >= a) break;
  }
  slots_along_x(b, ys, centre.x() - reach, centre.x() + reach, z, true);
  b.finish(fmt::format("octahedron mesh, {}, waist cut by a {}-pass zigzag", tool_word(sphere), ys.size()),
           sphere ? 2 : 1);
}

const std::vector<std::pair<std::string, Family>>& family_table() {
  static const std::vector<std::pair<std::string, Family>> table = {
      {"through_slots", through_slots},
      {"crossing_slots", crossing_slots},
      {"island_ring", island_ring},
      {"removed_piece", removed_piece},
      {"spiral", spiral},
      {"zigzag_cross", zigzag_cross},
      {"coincident", coincident},
      {"overlap", overlap},
      {"tangent", tangent},
      {"graze_face", graze_face},
      {"graze_edge", graze_edge},
      {"near_tolerance", near_tolerance},
      {"outside", outside},
      {"mesh_split", mesh_split},
  };
  return table;
}

Family family_named(const std::string& name) {
  for (const auto* table : {&family_table(), &motion_family_table()})
    for (const auto& [n, family] : *table)
      if (n == name) return family;
  throw morph::InputError("stress: unknown case family '" + name + "'");
}

/// One stream per (seed, index), decorrelated by hashing both.
std::uint64_t case_stream(std::uint64_t seed, std::size_t index) {
  CaseRandom mix(seed * 0x2545F4914F6CDD1DULL + 0x9E3779B97F4A7C15ULL);
  CaseRandom mixed(mix.next() ^ (static_cast<std::uint64_t>(index) * 0xD1B54A32D192ED03ULL));
  return mixed.next();
}

}  // namespace

const std::vector<std::string>& case_families() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> list;
    for (const auto& [name, family] : family_table()) list.push_back(name);
    return list;
  }();
  return names;
}

const std::vector<std::string>& motion_families() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> list;
    for (const auto& [name, family] : motion_family_table()) list.push_back(name);
    return list;
  }();
  return names;
}

std::vector<std::string> parse_families(const std::string& text) {
  std::vector<std::string> all = case_families();
  all.insert(all.end(), motion_families().begin(), motion_families().end());
  if (text == "classic" || text.empty()) return case_families();
  if (text == "motion") return motion_families();
  if (text == "all") return all;
  std::vector<std::string> chosen;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string name = text.substr(start, comma - start);
    if (std::find(all.begin(), all.end(), name) == all.end()) {
      std::string known;
      for (const auto& n : all) known += (known.empty() ? "" : ", ") + n;
      throw morph::InputError("--families: unknown family '" + name +
                              "' (give classic, motion, all, or names separated by commas: " + known + ")");
    }
    if (std::find(chosen.begin(), chosen.end(), name) == chosen.end()) chosen.push_back(name);
    start = comma + 1;
  }
  return chosen;
}

std::string case_name(std::size_t index) {
  return fmt::format("case_{:06d}", index);
}

StressCase make_case(std::uint64_t seed, std::size_t index, const CaseSpace& space) {
  if (space.families.empty()) throw morph::InputError("stress: no case family chosen");
  StressCase c;
  c.seed = seed;
  c.index = index;
  c.family = space.families[index % space.families.size()];
  const Family family = family_named(c.family);
  CaseRandom rng(case_stream(seed, index));
  Builder builder(c);
  builder.tolerance(draw_tolerance(rng));
  family(rng, builder);
  c.job["name"] = fmt::format("stress_{}_{}", seed, case_name(index));
  c.job["description"] = fmt::format(
      "morphmill stress case {} of seed {} (family {}: {}); expected pieces {}{}{}. Reproduce with: "
      "morphmill "
      "verify {}.json --output OUT --voxel {}",
      index, seed, c.family, c.variant, c.expected_pieces,
      c.expected_volume ? fmt::format(", expected volume {:.9g}", *c.expected_volume) : std::string(),
      c.expected_genus >= 0 ? fmt::format(", expected genus {}", c.expected_genus) : std::string(),
      case_name(index), c.voxel_size);
  return c;
}

std::string write_case(const StressCase& stress_case, const std::string& dir, const std::string& file_name) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw morph::IoError(dir + ": cannot create the directory: " + error.message());
  const fs::path job_path = fs::path(dir) / file_name;
  morph::write_file_atomically(job_path.string(), stress_case.job.dump(2) + "\n");
  if (stress_case.stock_mesh)
    write_mesh(*stress_case.stock_mesh, (fs::path(dir) / stress_case.stock_file).string());
  if (!stress_case.gcode_file.empty())
    morph::write_file_atomically((fs::path(dir) / stress_case.gcode_file).string(), stress_case.gcode_text);
  return job_path.string();
}

}  // namespace morphmill::stress
