// SPDX-License-Identifier: Apache-2.0
#include <morph/tool_profile.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace morph {

namespace {

using Eigen::Vector2d;

Vector2d on_piece(const Vector2d& centre, const Vector2d& radii, double angle) {
  return centre + Vector2d(radii.x() * std::cos(angle), radii.y() * std::sin(angle));
}

// Direction of travel (radians) at the start (end = false) or end of a piece.
double tangent_angle(const ProfilePiece& piece, bool end) {
  if (piece.kind == ProfilePiece::Kind::Segment) {
    const Vector2d d = piece.to - piece.from;
    const double angle = std::atan2(d.y(), d.x());
    return angle < -0.5 * M_PI ? angle + 2.0 * M_PI : angle;
  }
  const double phi = end ? piece.angle1 : piece.angle0;
  const double angle = std::atan2(piece.radii.y() * std::cos(phi), -piece.radii.x() * std::sin(phi));
  // A direction pointing left along -r is pi, not -pi: the profile's directions run over [0, pi].
  return angle < -0.5 * M_PI ? angle + 2.0 * M_PI : angle;
}

double segment_distance(const Vector2d& a, const Vector2d& b, const Vector2d& p) {
  const Vector2d d = b - a;
  const double dd = d.squaredNorm();
  const double t = dd > 0.0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm();
}

double endpoint_distance(const ProfilePiece& piece, const Vector2d& p) {
  return std::min((p - piece.from).norm(), (p - piece.to).norm());
}

// Unsigned distance from p to one piece.
double piece_distance(const ProfilePiece& piece, const Vector2d& p) {
  switch (piece.kind) {
    case ProfilePiece::Kind::Segment:
      return segment_distance(piece.from, piece.to, p);
    case ProfilePiece::Kind::Arc: {
      const Vector2d q = p - piece.centre;
      const double norm = q.norm();
      if (norm == 0.0) return piece.radii.x();
      // Whether q's direction is within the arc's turn from its start to its end (counter-
      // clockwise), by signs of cross products rather than angles: on either bounding ray both
      // answers give the same distance.
      const Vector2d start = piece.from - piece.centre, end = piece.to - piece.centre;
      auto cross = [](const Vector2d& a, const Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); };
      const bool within = piece.angle1 - piece.angle0 <= M_PI
                              ? cross(start, q) >= 0.0 && cross(q, end) >= 0.0
                              : !(cross(end, q) > 0.0 && cross(q, start) > 0.0);
      return within ? std::abs(norm - piece.radii.x()) : endpoint_distance(piece, p);
    }
    case ProfilePiece::Kind::Ellipse: {
      // A quarter ellipse: a point in the quadrant has its nearest ellipse point in that quadrant
      // (the ellipse is symmetric), so the whole ellipse's distance is the quarter's. Elsewhere
      // the nearest point of the profile lies on another piece; the ends bound this one's.
      const Vector2d q = p - piece.centre;
      const double mid = 0.5 * (piece.angle0 + piece.angle1);
      const double sx = std::cos(mid) >= 0.0 ? 1.0 : -1.0, sy = std::sin(mid) >= 0.0 ? 1.0 : -1.0;
      if (q.x() * sx < 0.0 || q.y() * sy < 0.0) return endpoint_distance(piece, p);
      return detail::ellipse_quadrant_distance(piece.radii.x(), piece.radii.y(), std::abs(q.x()),
                                               std::abs(q.y()));
    }
  }
  return std::numeric_limits<double>::infinity();
}

// Radius of one piece at height h, or -1 if the piece does not span h.
double piece_radius_at(const ProfilePiece& piece, double h) {
  const double lo = std::min(piece.from.y(), piece.to.y()), hi = std::max(piece.from.y(), piece.to.y());
  if (h < lo || h > hi) return -1.0;
  switch (piece.kind) {
    case ProfilePiece::Kind::Segment:
      if (hi == lo) return std::max(piece.from.x(), piece.to.x());
      return piece.from.x() +
             (h - piece.from.y()) / (piece.to.y() - piece.from.y()) * (piece.to.x() - piece.from.x());
    case ProfilePiece::Kind::Arc:
    case ProfilePiece::Kind::Ellipse: {
      const double s = std::clamp((h - piece.centre.y()) / piece.radii.y(), -1.0, 1.0);
      return piece.centre.x() + piece.radii.x() * std::sqrt(1.0 - s * s);
    }
  }
  return -1.0;
}

// Integrals over a piece of r dh and r^2 dh (exact).
std::pair<double, double> piece_integrals(const ProfilePiece& piece) {
  if (piece.kind == ProfilePiece::Kind::Segment) {
    const double dh = piece.to.y() - piece.from.y(), r0 = piece.from.x(), r1 = piece.to.x();
    return {dh * 0.5 * (r0 + r1), dh * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0};
  }
  // r = c + a cos(phi), h = k + b sin(phi), dh = b cos(phi) dphi.
  const double c = piece.centre.x(), a = piece.radii.x(), b = piece.radii.y();
  auto first = [&](double phi) {
    return b * (c * std::sin(phi) + a * (0.5 * phi + 0.25 * std::sin(2.0 * phi)));
  };
  auto second = [&](double phi) {
    const double s = std::sin(phi);
    return b * (c * c * s + 2.0 * c * a * (0.5 * phi + 0.25 * std::sin(2.0 * phi)) +
                a * a * (s - s * s * s / 3.0));
  };
  return {first(piece.angle1) - first(piece.angle0), second(piece.angle1) - second(piece.angle0)};
}

std::string point_text(const Vector2d& p) {
  std::ostringstream out;
  out.precision(6);
  out << "(" << p.x() << ", " << p.y() << ")";
  return out.str();
}

}  // namespace

ProfilePiece ProfilePiece::segment(const Vector2d& from, const Vector2d& to) {
  ProfilePiece piece;
  piece.kind = Kind::Segment;
  piece.from = from;
  piece.to = to;
  return piece;
}

ProfilePiece ProfilePiece::arc(const Vector2d& centre, double radius, double from_angle, double to_angle) {
  ProfilePiece piece;
  piece.kind = Kind::Arc;
  piece.centre = centre;
  piece.radii = Vector2d(radius, radius);
  piece.angle0 = from_angle;
  piece.angle1 = to_angle;
  piece.from = on_piece(centre, piece.radii, from_angle);
  piece.to = on_piece(centre, piece.radii, to_angle);
  return piece;
}

ProfilePiece ProfilePiece::ellipse(const Vector2d& centre, const Vector2d& radii, double from_angle,
                                   double to_angle) {
  ProfilePiece piece = arc(centre, 1.0, from_angle, to_angle);
  piece.kind = Kind::Ellipse;
  piece.radii = radii;
  piece.from = on_piece(centre, radii, from_angle);
  piece.to = on_piece(centre, radii, to_angle);
  return piece;
}

ToolProfile::ToolProfile(std::vector<ProfilePiece> pieces, double point_height, const std::string& field)
    : pieces_(std::move(pieces)), point_height_(point_height) {
  if (pieces_.empty()) throw ToolError(field, "a tool profile needs at least one piece");
  double scale = 0.0;
  for (const ProfilePiece& piece : pieces_) {
    if (!piece.from.allFinite() || !piece.to.allFinite() || !piece.centre.allFinite() ||
        !piece.radii.allFinite())
      throw ToolError(field, "a profile piece is not finite");
    scale = std::max({scale, piece.from.cwiseAbs().maxCoeff(), piece.to.cwiseAbs().maxCoeff()});
  }
  const double eps = 1e-9 * std::max(scale, 1e-300);
  if (!(scale > 0.0)) throw ToolError(field, "the profile has no size");
  if (pieces_.front().from.norm() > eps)
    throw ToolError(field, "the profile must start on the axis at the tip (0, 0), not at " +
                               point_text(pieces_.front().from));
  if (std::abs(pieces_.back().to.x()) > eps)
    throw ToolError(field, "the profile must end on the axis, not at " + point_text(pieces_.back().to));
  pieces_.front().from = Vector2d::Zero();
  pieces_.back().to.x() = 0.0;
  double previous_turn = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < pieces_.size(); ++i) {
    ProfilePiece& piece = pieces_[i];
    const std::string which = "piece " + std::to_string(i + 1) + " of the profile";
    if ((piece.to - piece.from).norm() <= eps && piece.kind == ProfilePiece::Kind::Segment)
      throw ToolError(field, which + " has zero length");
    if (piece.kind != ProfilePiece::Kind::Segment) {
      if (!(piece.radii.minCoeff() > 0.0)) throw ToolError(field, which + " has a radius <= 0");
      if (!(piece.angle1 > piece.angle0)) throw ToolError(field, which + " must turn counter-clockwise");
      if (piece.kind == ProfilePiece::Kind::Ellipse &&
          std::floor(piece.angle0 / (0.5 * M_PI) + 1e-9) != std::floor(piece.angle1 / (0.5 * M_PI) - 1e-9))
        throw ToolError(field, which + " (an ellipse) must stay within one quadrant");
    }
    if (i > 0) {
      const Vector2d& end = pieces_[i - 1].to;
      if ((piece.from - end).norm() > eps)
        throw ToolError(field, which + " starts at " + point_text(piece.from) +
                                   ", not where the previous one ends " + point_text(end));
      piece.from = end;
    }
    if (piece.from.x() < -eps || piece.to.x() < -eps)
      throw ToolError(field, which + " crosses the axis (r < 0)");
    const double start = tangent_angle(piece, false), finish = tangent_angle(piece, true);
    if (i == 0 && !(start >= -1e-12 && start < 0.5 * M_PI))
      throw ToolError(field,
                      "the profile must leave the tip outward and not downward (it would not be convex)");
    if (start < previous_turn - 1e-9 || finish < start - 1e-9)
      throw ToolError(field, which + " turns right: the profile is not convex");
    if (finish > M_PI + 1e-9 || start < -1e-12)
      throw ToolError(field, which + " goes down: the profile is not convex (heights must never fall)");
    previous_turn = finish;
    radius_ = std::max({radius_, piece.from.x(), piece.to.x()});
    if (piece.kind != ProfilePiece::Kind::Segment && piece.angle0 <= 0.0 && piece.angle1 >= 0.0)
      radius_ = std::max(radius_, piece.centre.x() + piece.radii.x());
  }
  if (previous_turn < 0.5 * M_PI)
    throw ToolError(field, "the profile must come back to the axis at its top (it would not be convex)");
  height_ = pieces_.back().to.y();
  if (!(height_ > 0.0)) throw ToolError(field, "the profile has no height");
  if (!(point_height_ >= 0.0 && point_height_ <= height_))
    throw ToolError(field, "the tool point must lie on the axis within the tool");
}

double ToolProfile::radius_at(double h) const {
  double r = -1.0;
  for (const ProfilePiece& piece : pieces_) r = std::max(r, piece_radius_at(piece, h));
  return std::max(r, 0.0);
}

double ToolProfile::signed_distance(double r, double h) const {
  const Vector2d p(r, h);
  double nearest = std::numeric_limits<double>::infinity();
  for (const ProfilePiece& piece : pieces_) nearest = std::min(nearest, piece_distance(piece, p));
  const bool inside = h > 0.0 && h < height_ && r < radius_at(h);
  return inside ? -nearest : nearest;
}

double ToolProfile::section_area() const {
  double sum = 0.0;
  for (const ProfilePiece& piece : pieces_) sum += piece_integrals(piece).first;
  return 2.0 * sum;
}

double ToolProfile::volume() const {
  double sum = 0.0;
  for (const ProfilePiece& piece : pieces_) sum += piece_integrals(piece).second;
  return M_PI * sum;
}

std::string ToolProfile::describe() const {
  std::ostringstream out;
  for (std::size_t i = 0; i < pieces_.size(); ++i) {
    const ProfilePiece& piece = pieces_[i];
    if (i) out << "; ";
    switch (piece.kind) {
      case ProfilePiece::Kind::Segment:
        out << "line " << point_text(piece.from) << "-" << point_text(piece.to);
        break;
      case ProfilePiece::Kind::Arc:
        out << "arc " << point_text(piece.from) << "-" << point_text(piece.to) << " about "
            << point_text(piece.centre);
        break;
      case ProfilePiece::Kind::Ellipse:
        out << "ellipse " << point_text(piece.from) << "-" << point_text(piece.to) << " about "
            << point_text(piece.centre) << " semi-axes " << point_text(piece.radii);
        break;
    }
  }
  return out.str();
}

namespace detail {

double ellipse_quadrant_distance(double e0, double e1, double y0, double y1) {
  if (e0 < e1) {
    std::swap(e0, e1);
    std::swap(y0, y1);
  }
  if (y1 > 0.0) {
    if (y0 > 0.0) {
      const double z0 = y0 / e0, z1 = y1 / e1;
      double g = z0 * z0 + z1 * z1 - 1.0;
      if (g == 0.0) return 0.0;
      const double r0 = (e0 / e1) * (e0 / e1);
      // The root s of (r0 z0 / (s + r0))^2 + (z1 / (s + 1))^2 = 1 in [z1 - 1, |(r0 z0, z1)| - 1].
      const double n0 = r0 * z0;
      double s0 = z1 - 1.0, s1 = g < 0.0 ? 0.0 : std::hypot(n0, z1) - 1.0, s = 0.0;
      for (int i = 0; i < 200; ++i) {
        s = 0.5 * (s0 + s1);
        if (s == s0 || s == s1 || s1 - s0 <= 4e-16 * std::max(1.0, std::abs(s))) break;
        const double a = n0 / (s + r0), b = z1 / (s + 1.0);
        g = a * a + b * b - 1.0;
        if (g > 0.0)
          s0 = s;
        else if (g < 0.0)
          s1 = s;
        else
          break;
      }
      const double x0 = r0 * y0 / (s + r0), x1 = y1 / (s + 1.0);
      return std::hypot(x0 - y0, x1 - y1);
    }
    return std::abs(y1 - e1);
  }
  const double numer0 = e0 * y0, denom0 = e0 * e0 - e1 * e1;
  if (numer0 < denom0) {
    const double xde0 = numer0 / denom0;
    const double x0 = e0 * xde0, x1 = e1 * std::sqrt(std::max(0.0, 1.0 - xde0 * xde0));
    return std::hypot(x0 - y0, x1);
  }
  return std::abs(y0 - e0);
}

}  // namespace detail

}  // namespace morph
