// SPDX-License-Identifier: Apache-2.0
#include "straight_sweep.h"

#include <morph/convex_minimum.h>
#include <morph/sweep_distance.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace vdb_ref::detail {

StraightSweep::StraightSweep(const morph::Tool& tool, const Eigen::Vector3d& a, const Eigen::Vector3d& b)
    : ball_end_(tool.type == morph::ToolType::BallEnd),
      radius_(tool.radius),
      length_(tool.length),
      a_(a),
      b_(b),
      d_(b - a),
      dd_(d_.squaredNorm()),
      centre_(ball_end_ ? Eigen::Vector3d(a + Eigen::Vector3d(0, 0, tool.radius)) : a),
      lowest_centre_z_(std::min(centre_.z(), centre_.z() + d_.z())),
      body_top_z_(std::max(centre_.z(), centre_.z() + d_.z()) + length_),
      hh_(d_.x() * d_.x() + d_.y() * d_.y()) {
  if (tool.sphere_or_ball_end()) return;
  general_ = &tool;
  const morph::ToolExtent e = morph::tool_extent(tool);
  const double half = 0.5 * (e.below + e.above);
  centre_ = a + Eigen::Vector3d(0, 0, half - e.below);
  bounding_radius_ = std::hypot(e.radius, half);
}

double StraightSweep::distance(const Eigen::Vector3d& p) const {
  return distance_within(p, -std::numeric_limits<double>::infinity(),
                         std::numeric_limits<double>::infinity());
}

double StraightSweep::distance_within(const Eigen::Vector3d& p, double floor, double ceiling) const {
  const Eigen::Vector3d pc = p - centre_;
  const double t = dd_ > 0.0 ? std::clamp(pc.dot(d_) / dd_, 0.0, 1.0) : 0.0;
  if (general_) {
    // The sweep of the tool's bounding ball contains the tool's sweep: its distance is a lower bound.
    const double bound = (pc - t * d_).norm() - bounding_radius_;
    if (bound >= ceiling) return bound;
    return morph::swept_signed_distance(*general_, a_, b_, p, ceiling);
  }
  const double ball = (pc - t * d_).norm() - radius_;
  if (!ball_end_) return ball;
  // Below every ball centre the body's nearest part is its bottom disc, inside the ball.
  if (p.z() <= lowest_centre_z_) return ball;
  // Inside the tip's sweep at or below the floor: the body cannot matter to the caller.
  if (ball <= floor) return ball;
  // Lower bound of the body sweep's distance: it lies within radius (horizontally) of the
  // centres' horizontal track and below the highest centre + length.
  const double th = hh_ > 0.0 ? std::clamp((pc.x() * d_.x() + pc.y() * d_.y()) / hh_, 0.0, 1.0) : 0.0;
  const double hx = pc.x() - th * d_.x(), hy = pc.y() - th * d_.y();
  const double horizontal = std::sqrt(hx * hx + hy * hy) - radius_;
  const double above = p.z() - body_top_z_;
  if (std::max(horizontal, above) >= std::min(ball, ceiling)) return ball;
  return std::min(ball, body_distance(p));
}

double StraightSweep::body_distance(const Eigen::Vector3d& p) const {
  auto body = [&](double t) {
    return morph::detail::capped_cylinder_distance(p - (centre_ + t * d_), radius_, 0.0, length_);
  };
  // The body distance is convex in t. Beside the body it is the horizontal distance to the centre
  // at the parameter nearest horizontally, within the parameters whose body spans p's height: try
  // that parameter and accept it if it is a local (hence global) minimum.
  double t_lo = 0.0, t_hi = 1.0;
  const double rise = d_.z(), below = p.z() - centre_.z();  // need below - t * rise in [0, length]
  if (std::abs(rise) > 1e-15) {
    const double ta = below / rise, tb = (below - length_) / rise;
    t_lo = std::max(0.0, std::min(ta, tb));
    t_hi = std::min(1.0, std::max(ta, tb));
  }
  if (t_lo <= t_hi) {
    const double px = p.x() - centre_.x(), py = p.y() - centre_.y();
    const double t =
        std::clamp(hh_ > 0.0 ? (px * d_.x() + py * d_.y()) / hh_ : 0.5 * (t_lo + t_hi), t_lo, t_hi);
    const double f = body(t), h = 1e-9;
    if ((t - h < 0.0 || body(t - h) >= f) && (t + h > 1.0 || body(t + h) >= f)) return f;
  }
  return morph::detail::golden_minimum(body, 0.0, 1.0).second;
}

}  // namespace vdb_ref::detail
