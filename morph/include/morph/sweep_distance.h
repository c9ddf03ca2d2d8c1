// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file sweep_distance.h
/// Exact truth: the signed distance to the volume a tool sweeps along a move, and to the
/// regularized partial erosion X \ (T (+) B) of a whole job. Used by the generator's tests,
/// the reference and the deviation tool alike.
#include <morph/job.h>

#include <Eigen/Geometry>
#include <limits>
#include <memory>

namespace morph {

/// Signed distance (job units, negative inside) from `p` to the volume swept by `tool` as its
/// tool point moves along the segment a->b. Sphere: the capsule, in closed form. Other convex
/// tools: min over t of the tool's signed distance, a convex 1-D minimisation solved to 1e-12.
/// With a `cutoff`: the same where the distance is below it by more than the rounding of a tool
/// distance (the same value, bit for bit; within that rounding of it, the same or a value at most
/// that rounding above it); elsewhere some value no less than `cutoff`. A nearest-sweep search
/// passes the nearest value so far: the searches along a move stop once the 1-Lipschitz bound
/// shows they cannot beat it (arcs and helices cost the most, a sine and cosine per tool position).
double swept_signed_distance(const Tool& tool, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& p,
                             double cutoff = std::numeric_limits<double>::infinity());

/// Same for a move of any kind. Arcs and helices: branch and bound over pieces of the exact
/// curve (the distance is 1-Lipschitz along it) refined by golden section, to 1e-9.
double swept_signed_distance(const Tool& tool, const Move& move, const Eigen::Vector3d& p,
                             double cutoff = std::numeric_limits<double>::infinity());

/// Parameter t in [0,1] of the tool position nearest to p along a straight segment (for
/// provenance and for the closest tool position).
double closest_sweep_parameter(const Tool& tool, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                               const Eigen::Vector3d& p);

/// Axis-aligned box containing the whole swept volume of `tool` along `move`.
Eigen::AlignedBox3d swept_bounds(const Tool& tool, const Move& move);

/// A run of consecutive line moves of one tool, each going on along the line of the run so far.
/// The sweep of [a, c] is the union of those of [a, b] and [b, c] when b lies on [a, c], so a run
/// sweeps exactly what its moves sweep; a query pays for one sweep, not for every step of a fine
/// raster (0.01 mm steps under a 3 mm tool put ~600 moves' bounds around every point).
struct SweptRun {
  Move move;  ///< the whole run, from its first move's start to its last's end
  const Tool* tool = nullptr;
  std::size_t first = 0;  ///< global index (Job::moves()) of its first move
  std::size_t count = 1;  ///< its moves; an arc is a run of its own
};

/// The job's moves as runs, in order. Joining is decided exactly (the doubles taken as exact
/// rationals): a move joins when it starts where the run ends, has the run's tool, and the run's
/// end lies on the segment from the run's start to the move's end.
std::vector<SweptRun> swept_runs(const Job& job);

/// The exact field of a whole job: f(p) = max(d_stock(p), -min_i d_sweep_i(p)). Its zero set is
/// the boundary of the regularized partial erosion; f < 0 inside the result. |f| equals the
/// distance to that boundary for points inside the result and is a lower bound elsewhere (it
/// is 1-Lipschitz), exact away from the creases where sweeps meet each other or the stock.
/// Queries are thread-safe; the sweeps of the job's runs (swept_runs) are found through a
/// bounding-volume hierarchy.
class ErosionField {
 public:
  explicit ErosionField(const Job& job);
  ~ErosionField();
  ErosionField(ErosionField&&) noexcept;
  ErosionField& operator=(ErosionField&&) noexcept;

  /// Signed distance to the stock (negative inside).
  double stock_distance(const Eigen::Vector3d& p) const;
  /// Signed distance to the union of all sweeps (negative inside); +infinity-like large value
  /// (the distance to the nearest sweep's bounds) when no sweep is near. `nearest_move` receives
  /// the global move index of the nearest sweep, -1 if none.
  double sweep_distance(const Eigen::Vector3d& p, int* nearest_move = nullptr) const;
  /// The erosion field f above.
  double value(const Eigen::Vector3d& p) const;

  const Job& job() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace morph
