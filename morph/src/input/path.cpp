// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/path.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace morph {

const char* to_string(MoveKind kind) {
  switch (kind) {
    case MoveKind::Rapid:
      return "rapid";
    case MoveKind::Linear:
      return "linear";
    case MoveKind::Arc:
      return "arc";
  }
  return "unknown";
}

namespace {

using ArcFrame = MovePoints::Frame;

ArcFrame arc_frame(const Move& m) {
  ArcFrame f;
  const Eigen::Vector3d s = m.start - m.center;
  const Eigen::Vector3d s_radial = s - s.dot(m.axis) * m.axis;
  f.r0 = s_radial.norm();
  f.u = f.r0 > 0.0 ? Eigen::Vector3d(s_radial / f.r0) : m.axis.unitOrthogonal();
  f.v = m.axis.cross(f.u);
  const Eigen::Vector3d e = m.end - m.center;
  f.rise = (m.end - m.start).dot(m.axis);
  f.r1 = (e - e.dot(m.axis) * m.axis).norm();
  const Eigen::Vector3d unclosed = m.center + s.dot(m.axis) * m.axis +
                                   f.r1 * (std::cos(m.sweep) * f.u + std::sin(m.sweep) * f.v) +
                                   f.rise * m.axis;
  f.closure = m.end - unclosed;
  return f;
}

}  // namespace

MovePoints::MovePoints(const Move& move) : move_(move) {
  if (!move.is_arc()) return;
  frame_ = arc_frame(move);
  base_ = move.center + (move.start - move.center).dot(move.axis) * move.axis;
}

Eigen::Vector3d MovePoints::operator()(double t) const {
  const Move& m = move_;
  if (!m.is_arc()) return m.start + t * (m.end - m.start);
  if (t <= 0.0) return m.start;
  if (t >= 1.0) return m.end;
  const ArcFrame& f = frame_;
  const double phi = t * m.sweep;
  const double r = f.r0 + t * (f.r1 - f.r0);
  return base_ + r * (std::cos(phi) * f.u + std::sin(phi) * f.v) + t * f.rise * m.axis + t * f.closure;
}

Eigen::Vector3d point_at(const Move& m, double t) {
  if (m.is_arc() && (t <= 0.0 || t >= 1.0)) return t <= 0.0 ? m.start : m.end;  // no frame needed
  return MovePoints(m)(t);
}

Eigen::Vector3d derivative_at(const Move& m, double t) {
  if (!m.is_arc()) return m.end - m.start;
  const ArcFrame f = arc_frame(m);
  const double phi = t * m.sweep;
  const double r = f.r0 + t * (f.r1 - f.r0);
  const Eigen::Vector3d radial = std::cos(phi) * f.u + std::sin(phi) * f.v;
  const Eigen::Vector3d tangential = -std::sin(phi) * f.u + std::cos(phi) * f.v;
  return (f.r1 - f.r0) * radial + r * m.sweep * tangential + f.rise * m.axis + f.closure;
}

double length(const Move& m) {
  if (!m.is_arc()) return (m.end - m.start).norm();
  const ArcFrame f = arc_frame(m);
  if (std::abs(f.r1 - f.r0) < 1e-12 * std::max(1.0, f.r0) && f.closure.norm() < 1e-12) {
    return std::hypot(f.r0 * m.sweep, f.rise);
  }
  // Composite Simpson on |derivative|: smooth integrand, 256 intervals is far below 1e-9 relative.
  const int n = 256;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += w * derivative_at(m, static_cast<double>(i) / n).norm();
  }
  return sum / (3.0 * n);
}

double chord_count(const Move& m, double chord_tolerance) {
  if (!m.is_arc()) return 1.0;
  const ArcFrame f = arc_frame(m);
  const double r = std::max(f.r0, f.r1);
  double n = 1.0;
  if (r > chord_tolerance && chord_tolerance > 0.0) {
    // Sagitta r(1 - cos(step/2)) <= tolerance.
    const double step = 2.0 * std::acos(1.0 - chord_tolerance / r);
    n = std::ceil(std::abs(m.sweep) / step);
  } else {
    n = std::ceil(std::abs(m.sweep) / (M_PI / 2.0));
  }
  return std::isfinite(n) ? std::max(n, 1.0) : std::numeric_limits<double>::infinity();
}

std::vector<double> chord_parameters(const Move& m, double chord_tolerance) {
  const double count = chord_count(m, chord_tolerance);
  if (!(count <= double(kMaxChordsPerArc))) {
    std::ostringstream message;
    message << std::setprecision(3) << "line " << m.line << ": an arc of " << std::abs(m.sweep) / (2 * M_PI)
            << " turns would need " << count << " chords at chord tolerance " << chord_tolerance
            << ", over the limit of " << kMaxChordsPerArc << " per arc; raise the tolerance or split the arc";
    throw LimitError(message.str());
  }
  const std::size_t n = static_cast<std::size_t>(count);
  std::vector<double> ts(n + 1);
  for (std::size_t i = 0; i <= n; ++i) ts[i] = static_cast<double>(i) / static_cast<double>(n);
  return ts;
}

}  // namespace morph
