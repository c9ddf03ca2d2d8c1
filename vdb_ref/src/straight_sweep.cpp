#include "straight_sweep.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vdb_ref::detail {

namespace {

// Signed distance to the vertical capped cylinder of radius r around the z axis between heights
// 0 and top, q relative to the bottom centre.
// (Plain square roots, not std::hypot: job coordinates are far from overflow, and hypot's
// extra care costs more than the rest of the evaluation.)
double capped_cylinder_distance(const Eigen::Vector3d& q, double r, double top) {
  const double dr = std::sqrt(q.x() * q.x() + q.y() * q.y()) - r;
  const double dz = std::max(-q.z(), q.z() - top);
  const double out_r = std::max(dr, 0.0), out_z = std::max(dz, 0.0);
  return std::sqrt(out_r * out_r + out_z * out_z) + std::min(std::max(dr, dz), 0.0);
}

// Minimum value of a convex function over [0, 1] by golden section to 1e-14 in the argument,
// the ends included (the same search as morph's, so the same value).
template <class F>
double golden_minimum_value(F&& f) {
  constexpr double kInvPhi = 0.6180339887498949;
  double lo = 0.0, hi = 1.0;
  double x1 = hi - kInvPhi * (hi - lo), x2 = lo + kInvPhi * (hi - lo);
  double f1 = f(x1), f2 = f(x2);
  for (int i = 0; i < 64 && hi - lo > 1e-14; ++i) {
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - kInvPhi * (hi - lo);
      f1 = f(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + kInvPhi * (hi - lo);
      f2 = f(x2);
    }
  }
  return std::min({f1, f2, f(lo), f(hi)});
}

}  // namespace

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
      hh_(d_.x() * d_.x() + d_.y() * d_.y()) {}

double StraightSweep::distance(const Eigen::Vector3d& p) const {
  return distance_within(p, -std::numeric_limits<double>::infinity(),
                         std::numeric_limits<double>::infinity());
}

double StraightSweep::distance_within(const Eigen::Vector3d& p, double floor, double ceiling) const {
  const Eigen::Vector3d pc = p - centre_;
  const double t = dd_ > 0.0 ? std::clamp(pc.dot(d_) / dd_, 0.0, 1.0) : 0.0;
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
  auto body = [&](double t) { return capped_cylinder_distance(p - (centre_ + t * d_), radius_, length_); };
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
  return golden_minimum_value(body);
}

}  // namespace vdb_ref::detail
