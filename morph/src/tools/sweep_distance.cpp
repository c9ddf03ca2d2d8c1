// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/mesh_distance.h>
#include <morph/sweep_distance.h>

#include <morph/convex_minimum.h>

#include "generator/exact_determinant.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace morph {

namespace {

using detail::capped_cylinder_distance;
using detail::golden_minimum;

double segment_parameter(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = b - a;
  const double dd = d.squaredNorm();
  return dd > 0.0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
}

// Stops a golden-section search along a path of length `length` once its bracket cannot go
// below `cutoff`: the tool distance is 1-Lipschitz in the tool point, so no value in [lo, hi] is
// below either sample less the bracket's path length. Until then the search is the same, so its
// value is the same wherever it is below the cutoff.
auto stop_at(double length, double cutoff) {
  return [length, cutoff](const detail::GoldenBracket& g, double* value) {
    *value = std::max(g.f1, g.f2) - (g.hi - g.lo) * length;
    return *value >= cutoff;
  };
}

// (parameter, distance) of the nearest tool position along a straight segment; where the
// distance is no less than `cutoff`, possibly only a value no less than it (parameter NaN).
std::pair<double, double> segment_sweep(const Tool& tool, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                        const Eigen::Vector3d& p, double cutoff) {
  const double length = (b - a).norm();
  switch (tool.type) {
    case ToolType::Sphere: {
      const double t = segment_parameter(a, b, p);
      return {t, (p - (a + t * (b - a))).norm() - tool.radius};
    }
    case ToolType::BallEnd: {
      // The tip ball sweeps a capsule (closed form); the body cylinder's distance is convex in t.
      const Eigen::Vector3d lift(0, 0, tool.radius);
      const double tb = segment_parameter(a + lift, b + lift, p);
      const double ball = (p - (a + lift + tb * (b - a))).norm() - tool.radius;
      // Below every ball centre of the move, the body's nearest part is its bottom disc, which lies
      // inside the ball: the ball alone decides (the common case under a cutting path).
      if (p.z() <= std::min(a.z(), b.z()) + tool.radius) return {tb, ball};
      // The body matters only where it could beat the ball and the cutoff.
      const double beat = std::min(ball, cutoff);
      const auto body = golden_minimum(
          [&](double t) {
            return capped_cylinder_distance(p - (a + lift + t * (b - a)), tool.radius, 0.0, tool.length);
          },
          0.0, 1.0, stop_at(length, beat));
      return ball <= body.second ? std::make_pair(tb, ball) : body;
    }
    default: {
      return golden_minimum([&](double t) { return tool_signed_distance(tool, a + t * (b - a), p); }, 0.0,
                            1.0, stop_at(length, cutoff));
    }
  }
}

// Branch and bound along an arc: the tool distance is 1-Lipschitz in the tool point, so a piece
// of path length L around a sample with value f cannot go below f - L/2. Pieces that cannot go
// below the best value found or below `cutoff` are left out: every value they could give is no
// less (but for the rounding of the values the bound is taken from), so the minimum is the same
// value wherever it is below the cutoff by more than that rounding.
std::pair<double, double> arc_sweep(const Tool& tool, const Move& move, const Eigen::Vector3d& p,
                                    double cutoff) {
  const double total = length(move);
  const MovePoints point_at_t(move);
  auto f = [&](double t) { return tool_signed_distance(tool, point_at_t(t), p); };
  struct Piece {
    double t0, t1, value, bound;
  };
  const int initial = std::max(8, static_cast<int>(std::ceil(std::abs(move.sweep) / (M_PI / 16))));
  std::vector<Piece> pieces;
  std::pair<double, double> best{0.0, std::numeric_limits<double>::infinity()};
  for (int i = 0; i < initial; ++i) {
    const double t0 = static_cast<double>(i) / initial, t1 = static_cast<double>(i + 1) / initial;
    const double v = f(0.5 * (t0 + t1));
    if (v < best.second) best = {0.5 * (t0 + t1), v};
    pieces.push_back({t0, t1, v, v - 0.5 * (t1 - t0) * total});
  }
  const double stop_length = std::max(1e-9, std::min(0.02 * total, 0.25 * std::max(tool.radius, 1e-6)));
  std::vector<Piece> leaves;
  while (!pieces.empty()) {
    const Piece piece = pieces.back();
    pieces.pop_back();
    if (piece.bound >= std::min(best.second, cutoff)) continue;
    if ((piece.t1 - piece.t0) * total <= stop_length) {
      leaves.push_back(piece);
      continue;
    }
    const double tm = 0.5 * (piece.t0 + piece.t1);
    for (const auto& [a, b] : {std::make_pair(piece.t0, tm), std::make_pair(tm, piece.t1)}) {
      const double v = f(0.5 * (a + b));
      if (v < best.second) best = {0.5 * (a + b), v};
      pieces.push_back({a, b, v, v - 0.5 * (b - a) * total});
    }
  }
  // Lowest bound first, and a leaf's search stopped once its bracket cannot beat the best: every
  // value left out is no less than one found, so the minimum is the same value.
  std::sort(leaves.begin(), leaves.end(), [](const Piece& a, const Piece& b) {
    return a.bound < b.bound || (a.bound == b.bound && a.t0 < b.t0);
  });
  for (const Piece& leaf : leaves) {
    const double beat = std::min(best.second, cutoff);
    if (leaf.bound >= beat) break;
    const auto local = golden_minimum(f, leaf.t0, leaf.t1, stop_at(total, beat));
    if (local.second < best.second) best = local;
  }
  return best;
}

}  // namespace

double swept_signed_distance(const Tool& tool, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& p, double cutoff) {
  return segment_sweep(tool, a, b, p, cutoff).second;
}

double swept_signed_distance(const Tool& tool, const Move& move, const Eigen::Vector3d& p, double cutoff) {
  if (!move.is_arc()) return segment_sweep(tool, move.start, move.end, p, cutoff).second;
  return arc_sweep(tool, move, p, cutoff).second;
}

double closest_sweep_parameter(const Tool& tool, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                               const Eigen::Vector3d& p) {
  return segment_sweep(tool, a, b, p, std::numeric_limits<double>::infinity()).first;
}

Eigen::AlignedBox3d swept_bounds(const Tool& tool, const Move& move) {
  Eigen::AlignedBox3d path_box;
  double pad = 0.0;
  if (move.is_arc()) {
    const double radius = (move.start - move.center).norm();
    const double chord = std::max(1e-9, 1e-3 * radius);
    for (double t : chord_parameters(move, chord)) path_box.extend(point_at(move, t));
    pad = chord;
  } else {
    path_box.extend(move.start);
    path_box.extend(move.end);
  }
  const ToolExtent e = tool_extent(tool);
  Eigen::Vector3d lo = path_box.min() - Eigen::Vector3d(e.radius + pad, e.radius + pad, e.below + pad);
  Eigen::Vector3d hi = path_box.max() + Eigen::Vector3d(e.radius + pad, e.radius + pad, e.above + pad);
  return Eigen::AlignedBox3d(lo, hi);
}

namespace {

// Whether b lies on the closed segment [a, c], decided exactly: the three projections' orientation
// determinants vanish (the doubles taken as exact rationals) and b is between a and c on each axis.
bool on_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  for (int axis = 0; axis < 3; ++axis)
    if (b[axis] < std::min(a[axis], c[axis]) || b[axis] > std::max(a[axis], c[axis])) return false;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const exact::ExactRows rows({exact::Row{a[u], a[v], 1.0, 0.0}, exact::Row{b[u], b[v], 1.0, 0.0},
                                 exact::Row{c[u], c[v], 1.0, 0.0}, exact::Row{}},
                                3);
    if (rows.minor_sign(0, 1, 2) != 0) return false;
  }
  return true;
}

}  // namespace

std::vector<SweptRun> swept_runs(const Job& job) {
  const std::vector<const Move*> moves = job.moves();
  std::vector<SweptRun> runs;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const Move& m = *moves[i];
    const Tool* tool = &job.tool_of(m);
    if (!runs.empty()) {
      SweptRun& run = runs.back();
      if (!m.is_arc() && !run.move.is_arc() && run.tool == tool && run.move.end == m.start &&
          on_segment(run.move.start, m.start, m.end)) {
        run.move.end = m.end;
        ++run.count;
        continue;
      }
    }
    runs.push_back({m, tool, i, 1});
  }
  return runs;
}

struct ErosionField::Impl {
  const Job* job = nullptr;
  std::vector<const Move*> moves;
  std::vector<SweptRun> runs;
  AabbTree tree;
  double max_depth = 0.0;  // no sweep is deeper than its tool's radius
  std::optional<MeshDistance> stock_mesh;

  // The global index of the move of `run` that holds its tool position nearest to p.
  std::size_t move_nearest(const SweptRun& run, const Eigen::Vector3d& p) const {
    if (run.count == 1) return run.first;
    const Eigen::Vector3d& a = run.move.start;
    const Eigen::Vector3d d = run.move.end - a;
    const double t = closest_sweep_parameter(*run.tool, a, run.move.end, p) * d.squaredNorm();
    std::size_t lo = run.first, hi = run.first + run.count - 1;
    while (lo < hi) {  // the first move whose end is at or beyond t along the run
      const std::size_t mid = lo + (hi - lo) / 2;
      if ((moves[mid]->end - a).dot(d) < t)
        lo = mid + 1;
      else
        hi = mid;
    }
    return lo;
  }
};

ErosionField::ErosionField(const Job& job) : impl_(std::make_unique<Impl>()) {
  impl_->job = &job;
  impl_->moves = job.moves();
  impl_->runs = swept_runs(job);
  std::vector<Eigen::AlignedBox3d> boxes;
  boxes.reserve(impl_->runs.size());
  for (const SweptRun& run : impl_->runs) {
    impl_->max_depth = std::max(impl_->max_depth, run.tool->radius);
    boxes.push_back(swept_bounds(*run.tool, run.move));
  }
  impl_->tree = AabbTree(std::move(boxes));
  if (job.stock.type == StockType::Mesh) impl_->stock_mesh.emplace(job.stock.mesh);
}

ErosionField::~ErosionField() = default;
ErosionField::ErosionField(ErosionField&&) noexcept = default;
ErosionField& ErosionField::operator=(ErosionField&&) noexcept = default;

const Job& ErosionField::job() const {
  return *impl_->job;
}

double ErosionField::stock_distance(const Eigen::Vector3d& p) const {
  if (impl_->stock_mesh) return impl_->stock_mesh->signed_distance(p);
  return analytic_signed_distance(impl_->job->stock, p);
}

double ErosionField::sweep_distance(const Eigen::Vector3d& p, int* nearest_move) const {
  double best = std::numeric_limits<double>::infinity();
  const std::int64_t item = impl_->tree.nearest(
      p,
      [&](std::size_t i, double nearest_so_far) {
        return swept_signed_distance(*impl_->runs[i].tool, impl_->runs[i].move, p, nearest_so_far);
      },
      &best, impl_->max_depth);
  if (nearest_move)
    *nearest_move = item < 0 ? -1 : static_cast<int>(impl_->move_nearest(impl_->runs[item], p));
  return best;
}

double ErosionField::value(const Eigen::Vector3d& p) const {
  return std::max(stock_distance(p), -sweep_distance(p));
}

}  // namespace morph
