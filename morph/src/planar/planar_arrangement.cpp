// SPDX-License-Identifier: Apache-2.0
// The arrangement behind planar::erode, dilate and classical_erosion: candidate curves split at
// all their mutual intersections, pieces classified at their midpoints, kept pieces linked.
#include <morph/exceptions.h>
#include <morph/planar_erosion.h>
#include <morph/union_find.h>
#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <sstream>

#include "planar/planar_grid.h"
#include "planar/planar_intersect.h"
#include "planar/planar_loops.h"

namespace morph::planar {

namespace {

struct Hit {
  std::uint32_t a, b;
  double ta, tb;
  Vec2 point;
};

struct Split {
  std::uint32_t curve;
  double t;
  std::uint32_t point;
};

/// A sub-curve between two split points of candidate curve `curve`.
struct PieceRef {
  std::uint32_t curve;
  double t0, t1;
  std::uint32_t u, v;  ///< vertices at t0 and t1
};

Box2 inflated(Box2 box, double by) {
  box.min().array() -= by;
  box.max().array() += by;
  return box;
}

/// Merges points closer than eps into vertices; returns the vertex of each point and their count.
std::vector<std::uint32_t> merge_points(const std::vector<Vec2>& points, const Box2& extent, double eps,
                                        ExecutionPolicy policy, std::size_t& vertex_count) {
  const std::size_t n = points.size();
  const double cell = 2.0 * eps;
  auto key_of = [&](long ix, long iy) {
    return (static_cast<std::uint64_t>(ix) << 32) | static_cast<std::uint64_t>(iy);
  };
  auto ix_of = [&](const Vec2& p) {
    return static_cast<long>(std::floor((p.x() - extent.min().x()) / cell)) + 2;
  };
  auto iy_of = [&](const Vec2& p) {
    return static_cast<long>(std::floor((p.y() - extent.min().y()) / cell)) + 2;
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
  for_each_index(policy, 0, n, [&](std::size_t i) {
    keyed[i] = {key_of(ix_of(points[i]), iy_of(points[i])), static_cast<std::uint32_t>(i)};
  });
  std::sort(keyed.begin(), keyed.end());
  tbb::enumerable_thread_specific<std::vector<std::pair<std::uint32_t, std::uint32_t>>> local;
  for_each_index(policy, 0, n, [&](std::size_t i) {
    const long ix = ix_of(points[i]), iy = iy_of(points[i]);
    auto& out = local.local();
    for (long x = ix - 1; x <= ix + 1; ++x) {
      auto it = std::lower_bound(keyed.begin(), keyed.end(), std::make_pair(key_of(x, iy - 1), 0u));
      const std::uint64_t last = key_of(x, iy + 1);
      for (; it != keyed.end() && it->first <= last; ++it)
        if (it->second > i && (points[it->second] - points[i]).squaredNorm() <= eps * eps)
          out.emplace_back(static_cast<std::uint32_t>(i), it->second);
    }
  });
  UnionFind sets(n);
  for (const auto& pairs : local)
    for (const auto& [a, b] : pairs) sets.unite(a, b);
  std::vector<std::uint32_t> vertex(n), id(n, UINT32_MAX);
  vertex_count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t root = sets.find(static_cast<std::uint32_t>(i));
    if (id[root] == UINT32_MAX) id[root] = static_cast<std::uint32_t>(vertex_count++);
    vertex[i] = id[root];
  }
  return vertex;
}

/// Decides, at a piece's midpoint m with left normal nu, on which sides of the piece the result
/// lies, from the exact distances to the moves and the position in the stock.
class Classifier {
 public:
  Classifier(const Region* stock, const std::vector<Curve>& stock_curves, const Trajectory& moves,
             const std::vector<std::uint32_t>& near, double radius, double eps_on, const Box2& extent)
      : stock_(stock),
        stock_curves_(stock_curves),
        moves_(moves),
        near_(near),
        radius_(radius),
        eps_on_(eps_on),
        move_boxes_(boxes_of_moves()),
        move_grid_(move_boxes_, extent, mean_size(move_boxes_, 2.0 * radius)),
        stock_boxes_(boxes_of_stock()),
        stock_grid_(stock_boxes_, extent, cell_for_stock(extent)) {}

  /// +1: the result is on the left of the piece only; -1: on the right only; 0: on both or neither.
  int classify(const Vec2& m, const Vec2& nu) const {
    bool covered_left = false, covered_right = false;
    const std::size_t cell = move_grid_.cell_of(m);
    for (const std::uint32_t* it = move_grid_.begin(cell); it != move_grid_.end(cell); ++it) {
      if (!move_boxes_[*it].contains(m)) continue;
      const ClosestPoint cp = closest_point(moves_[near_[*it]], m);
      if (cp.distance < radius_ - eps_on_) return 0;  // strictly inside a dilation
      if (cp.distance > radius_ + eps_on_) continue;
      const double side = (m - cp.point).dot(nu);  // the dilation's outward normal against nu
      if (side < 0.0) covered_left = true;
      if (side > 0.0) covered_right = true;
    }
    bool left = true, right = true;
    if (stock_) {
      Vec2 outward;
      if (on_stock_boundary(m, outward)) {
        left = outward.dot(nu) < 0.0;
        right = outward.dot(nu) > 0.0;
      } else {
        left = right = inside_stock(m);
      }
      left = left && !covered_left;
      right = right && !covered_right;
    } else {
      left = covered_left;
      right = covered_right;
    }
    if (left == right) return 0;
    return left ? 1 : -1;
  }

 private:
  /// Cells about as large as the boxes on average: a long move is listed in a few cells, not thousands.
  static double mean_size(const std::vector<Box2>& boxes, double at_least) {
    double sum = 0.0;
    for (const Box2& b : boxes) sum += b.sizes().maxCoeff();
    return std::max(at_least, boxes.empty() ? at_least : sum / static_cast<double>(boxes.size()));
  }
  std::vector<Box2> boxes_of_moves() const {
    std::vector<Box2> boxes(near_.size());
    for (std::size_t i = 0; i < near_.size(); ++i)
      boxes[i] = inflated(dilation_bounds(moves_[near_[i]], radius_), eps_on_);
    return boxes;
  }
  std::vector<Box2> boxes_of_stock() const {
    std::vector<Box2> boxes(stock_curves_.size());
    for (std::size_t i = 0; i < stock_curves_.size(); ++i)
      boxes[i] = inflated(bounds(stock_curves_[i]), eps_on_);
    return boxes;
  }
  double cell_for_stock(const Box2& extent) const {
    return extent.sizes().maxCoeff() / std::max(1.0, std::sqrt(static_cast<double>(stock_curves_.size())));
  }

  bool on_stock_boundary(const Vec2& m, Vec2& outward) const {
    const std::size_t cell = stock_grid_.cell_of(m);
    double best = eps_on_;
    bool found = false;
    for (const std::uint32_t* it = stock_grid_.begin(cell); it != stock_grid_.end(cell); ++it) {
      if (!stock_boxes_[*it].contains(m)) continue;
      const Curve& c = stock_curves_[*it];
      const ClosestPoint cp = closest_point(c, m);
      if (cp.distance <= best) {
        best = cp.distance;
        outward = -left_normal(tangent_at(c, cp.t));  // stock loops keep the stock on their left
        found = true;
      }
    }
    return found;
  }

  bool inside_stock(const Vec2& m) const {
    // Every curve the ray towards +x can cross is listed in the cells of m's row from m onwards.
    const int row = stock_grid_.row_of(m.y());
    std::vector<std::uint32_t> seen;
    for (int col = stock_grid_.column_of(m.x()); col < stock_grid_.columns(); ++col) {
      const std::size_t cell = static_cast<std::size_t>(row) * stock_grid_.columns() + col;
      for (const std::uint32_t* it = stock_grid_.begin(cell); it != stock_grid_.end(cell); ++it)
        seen.push_back(*it);
    }
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    int n = 0;
    for (const std::uint32_t i : seen)
      if (stock_boxes_[i].max().x() >= m.x() && stock_boxes_[i].min().y() <= m.y() &&
          stock_boxes_[i].max().y() >= m.y())
        n += crossings(stock_curves_[i], m);
    return (n & 1) != 0;
  }

  const Region* stock_;
  const std::vector<Curve>& stock_curves_;
  const Trajectory& moves_;
  const std::vector<std::uint32_t>& near_;
  double radius_, eps_on_;
  std::vector<Box2> move_boxes_;
  UniformGrid move_grid_;
  std::vector<Box2> stock_boxes_;
  UniformGrid stock_grid_;
};

void check_interrupt(const PlanarOptions& options) {
  if (options.progress && options.progress->interrupted()) throw Interrupted("planar erosion interrupted");
}

}  // namespace

/// The arrangement: stock \ union of the moves' dilations, or the union alone if stock is null.
PlanarResult arrange(const Region* stock, const Trajectory& moves, double radius,
                     const PlanarOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  if (!(radius > 0.0) || !std::isfinite(radius)) {
    std::ostringstream message;
    message << "planar erosion: the tool radius must be positive and finite, got " << radius;
    throw InputError(message.str());
  }
  PlanarResult result;
  PlanarStats& stats = result.stats;
  stats.moves = moves.size();

  // Which moves can matter, the extent of the work and the one length scale of its decisions.
  Box2 extent;
  std::vector<Curve> stock_curves;
  if (stock) {
    extent = bounds(*stock);
    std::int32_t k = 0;
    for (const Loop& loop : stock->loops)
      for (const Curve& c : loop.curves) {
        stock_curves.push_back(c);
        stock_curves.back().from = Provenance{Origin::Stock, k++, c.from.line};
      }
  }
  std::vector<std::uint32_t> near;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const Box2 box = dilation_bounds(moves[i], radius);
    if (stock && !box.intersects(extent)) continue;
    near.push_back(static_cast<std::uint32_t>(i));
    if (!stock) extent.extend(box);
  }
  stats.moves_near_stock = near.size();
  if (extent.isEmpty()) return result;
  const double scale = std::max({extent.sizes().maxCoeff(), extent.min().cwiseAbs().maxCoeff(),
                                 extent.max().cwiseAbs().maxCoeff(), radius});
  const double eps = 1e-9 * scale, eps_on = 4.0 * eps;
  extent = inflated(extent, 2.0 * eps);

  // Candidate curves: the stock's boundary first (it wins ties), then each move's dilation boundary.
  // Full circles become two halves: every split point of a curve is then an end some other
  // coincident curve can see (a plunge's circle and the half circle behind the next move's start).
  std::vector<Curve> curves;
  auto add_candidate = [&](const Curve& c) {
    if (!(c.is_arc() && c.start == c.end)) return curves.push_back(c);
    const double a0 = start_angle(c), half = 0.5 * c.sweep;
    Curve first = make_arc(c.center, c.radius, a0, half, c.from),
          second = make_arc(c.center, c.radius, a0 + half, half, c.from);
    first.start = c.start;
    second.start = first.end;
    second.end = c.start;
    curves.push_back(first);
    curves.push_back(second);
  };
  for (const Curve& c : stock_curves) add_candidate(c);
  const std::size_t stock_count = curves.size();
  std::vector<Curve> boundary;
  for (const std::uint32_t i : near) dilation_boundary(moves[i], radius, boundary);
  for (const Curve& c : boundary) add_candidate(c);
  if (stock)
    curves.erase(std::remove_if(curves.begin() + static_cast<long>(stock_count), curves.end(),
                                [&](const Curve& c) { return !bounds(c).intersects(extent); }),
                 curves.end());
  stats.candidate_curves = curves.size();
  check_interrupt(options);

  // All pairwise meeting points, cell by cell.
  std::vector<Box2> boxes(curves.size());
  double mean_size = 0.0;
  for (std::size_t i = 0; i < curves.size(); ++i) {
    boxes[i] = inflated(bounds(curves[i]), eps);
    if (i >= stock_count) mean_size += boxes[i].sizes().maxCoeff();
  }
  mean_size = curves.size() > stock_count ? mean_size / static_cast<double>(curves.size() - stock_count)
                                          : extent.sizes().maxCoeff() / 16.0;
  const UniformGrid grid(boxes, extent, mean_size);
  if (options.progress) options.progress->begin("planar: split", grid.cell_count());
  tbb::enumerable_thread_specific<std::vector<Hit>> local_hits;
  for_each_index(options.policy, 0, grid.cell_count(), [&](std::size_t cell) {
    auto& out = local_hits.local();
    std::vector<CurveHit> hits;
    for (const std::uint32_t* i = grid.begin(cell); i != grid.end(cell); ++i)
      for (const std::uint32_t* j = i + 1; j != grid.end(cell); ++j) {
        if (*i < stock_count && *j < stock_count) continue;  // stock loops meet only at their vertices
        if (!boxes[*i].intersects(boxes[*j]) || grid.first_common_cell(boxes[*i], boxes[*j]) != cell)
          continue;
        hits.clear();
        intersect(curves[*i], curves[*j], eps, hits);
        for (const CurveHit& h : hits) out.push_back({*i, *j, h.ta, h.tb, h.point});
      }
    if (options.progress) options.progress->advance(1);
  });
  if (options.progress) options.progress->end();
  std::vector<Hit> hits;
  for (auto& part : local_hits) hits.insert(hits.end(), part.begin(), part.end());
  std::sort(hits.begin(), hits.end(), [](const Hit& x, const Hit& y) {
    return std::tie(x.a, x.b, x.ta, x.tb) < std::tie(y.a, y.b, y.ta, y.tb);
  });
  stats.intersections = hits.size();
  check_interrupt(options);

  // Split points: every curve's ends and each hit on both curves.
  std::vector<Vec2> points;
  std::vector<Split> splits;
  for (std::uint32_t i = 0; i < curves.size(); ++i) {
    const Curve& c = curves[i];
    splits.push_back({i, 0.0, static_cast<std::uint32_t>(points.size())});
    points.push_back(c.start);
    splits.push_back({i, 1.0, static_cast<std::uint32_t>(points.size())});
    points.push_back(c.end);
  }
  for (const Hit& h : hits) {
    const auto p = static_cast<std::uint32_t>(points.size());
    points.push_back(h.point);
    splits.push_back({h.a, h.ta, p});
    splits.push_back({h.b, h.tb, p});
  }
  std::size_t vertex_count = 0;
  const std::vector<std::uint32_t> vertex_of =
      merge_points(points, extent, eps, options.policy, vertex_count);
  stats.vertices = vertex_count;
  std::vector<Vec2> vertex_position(vertex_count);
  {
    std::vector<char> placed(vertex_count, 0);
    for (std::size_t i = 0; i < points.size(); ++i)
      if (!placed[vertex_of[i]]) {
        placed[vertex_of[i]] = 1;
        vertex_position[vertex_of[i]] = points[i];
      }
  }
  std::sort(splits.begin(), splits.end(), [](const Split& x, const Split& y) {
    return std::tie(x.curve, x.t, x.point) < std::tie(y.curve, y.t, y.point);
  });
  std::vector<PieceRef> pieces;
  for (std::size_t k = 0; k + 1 < splits.size(); ++k) {
    const Split& s0 = splits[k];
    if (splits[k + 1].curve != s0.curve) continue;
    // Follow to the next split point on this curve that is another vertex.
    std::size_t next = k + 1;
    const std::uint32_t u = vertex_of[s0.point];
    if (vertex_of[splits[next].point] == u) continue;
    pieces.push_back({s0.curve, s0.t, splits[next].t, u, vertex_of[splits[next].point]});
  }
  stats.pieces = pieces.size();
  check_interrupt(options);

  // Classification at each piece's midpoint.
  const Classifier classifier(stock, stock_curves, moves, near, radius, eps_on, extent);
  std::vector<signed char> side(pieces.size(), 0);
  if (options.progress) options.progress->begin("planar: classify", pieces.size());
  for_each_index(options.policy, 0, pieces.size(), [&](std::size_t i) {
    const PieceRef& p = pieces[i];
    const Curve& c = curves[p.curve];
    const double tm = 0.5 * (p.t0 + p.t1);
    side[i] = static_cast<signed char>(classifier.classify(point_at(c, tm), left_normal(tangent_at(c, tm))));
    if (options.progress && (i & 4095) == 0) options.progress->advance(4096);
  });
  if (options.progress) options.progress->end();

  // Kept pieces, oriented with the result on their left; copies (same ends, same midpoint) dropped.
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < pieces.size(); ++i)
    if (side[i] != 0) kept.push_back(i);
  auto ends_of = [&](std::size_t i) {
    return side[i] > 0 ? std::make_pair(pieces[i].u, pieces[i].v) : std::make_pair(pieces[i].v, pieces[i].u);
  };
  auto midpoint_of = [&](std::size_t i) {
    return point_at(curves[pieces[i].curve], 0.5 * (pieces[i].t0 + pieces[i].t1));
  };
  std::stable_sort(kept.begin(), kept.end(),
                   [&](std::size_t a, std::size_t b) { return ends_of(a) < ends_of(b); });
  std::vector<Curve> loop_pieces;
  std::vector<std::uint32_t> from, to;
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const std::size_t i = kept[k];
    bool copy = false;
    for (std::size_t j = k; j-- > 0 && ends_of(kept[j]) == ends_of(i);)
      if ((midpoint_of(kept[j]) - midpoint_of(i)).norm() <= eps_on) copy = true;
    if (copy) {
      ++stats.coincident_copies;
      continue;
    }
    const PieceRef& p = pieces[i];
    Curve piece = sub_curve(curves[p.curve], p.t0, p.t1, vertex_position[p.u], vertex_position[p.v]);
    if (side[i] < 0) piece = reversed(piece);
    loop_pieces.push_back(piece);
    from.push_back(ends_of(i).first);
    to.push_back(ends_of(i).second);
  }
  stats.pieces_kept = loop_pieces.size();
  result.region = group_pieces(link_loops(loop_pieces, from, to, vertex_count, 1e-6 * scale));
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace morph::planar
