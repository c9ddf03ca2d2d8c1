// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/tool.h>

#include <morph/convex_minimum.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>
#include <vector>

namespace morph {

namespace {

using Eigen::Vector2d;
using Piece = ProfilePiece;

constexpr double kDegree = M_PI / 180.0;

std::string number_text(double x) {
  std::ostringstream out;
  out.precision(6);
  out << x;
  return out.str();
}

double positive(const char* field, double x) {
  if (!std::isfinite(x)) throw ToolError(field, "must be a finite number, got " + number_text(x));
  if (!(x > 0.0)) throw ToolError(field, "must be greater than 0, got " + number_text(x));
  return x;
}

double non_negative(const char* field, double x) {
  if (!std::isfinite(x)) throw ToolError(field, "must be a finite number, got " + number_text(x));
  if (!(x >= 0.0)) throw ToolError(field, "must not be negative, got " + number_text(x));
  return x;
}

double angle_in(const char* field, double degrees, double lo, bool lo_open, double hi, const char* what) {
  if (!std::isfinite(degrees) || (lo_open ? !(degrees > lo) : !(degrees >= lo)) || !(degrees < hi))
    throw ToolError(field, std::string("must be ") + what + ", got " + number_text(degrees));
  return degrees;
}

// A tool with a profile; radius from the profile.
Tool with_profile(ToolType type, std::vector<Piece> pieces, double point_height, const char* field) {
  Tool tool;
  tool.type = type;
  tool.profile = ToolProfile(std::move(pieces), point_height, field);
  tool.radius = tool.profile.radius();
  return tool;
}

// Flat tip of tip_radius, cone to radius at cone_height, cylinder up to length, flat top.
std::vector<Piece> cone_pieces(double tip_radius, double radius, double cone_height, double length) {
  std::vector<Piece> pieces;
  if (tip_radius > 0.0) pieces.push_back(Piece::segment({0, 0}, {tip_radius, 0}));
  pieces.push_back(Piece::segment({tip_radius, 0}, {radius, cone_height}));
  if (length > cone_height) pieces.push_back(Piece::segment({radius, cone_height}, {radius, length}));
  pieces.push_back(Piece::segment({radius, length}, {0, length}));
  return pieces;
}

}  // namespace

const char* to_string(ToolType type) {
  switch (type) {
    case ToolType::Sphere:
      return "sphere";
    case ToolType::BallEnd:
      return "ballend";
    case ToolType::Flat:
      return "flat";
    case ToolType::Bullnose:
      return "bullnose";
    case ToolType::Conical:
      return "conical";
    case ToolType::Tapered:
      return "tapered";
    case ToolType::TaperedBall:
      return "tapered_ball";
    case ToolType::Spheroid:
      return "spheroid";
    case ToolType::Apt:
      return "apt";
  }
  return "unknown";
}

ToolType tool_type_from_string(const std::string& name, const std::string& where) {
  for (ToolType t :
       {ToolType::Sphere, ToolType::BallEnd, ToolType::Flat, ToolType::Bullnose, ToolType::Conical,
        ToolType::Tapered, ToolType::TaperedBall, ToolType::Spheroid, ToolType::Apt})
    if (name == to_string(t)) return t;
  if (name == "ball") return ToolType::BallEnd;
  if (name == "vbit") return ToolType::Conical;
  if (name == "snubnose") return ToolType::Tapered;
  throw InputError(where + ": unknown tool type '" + name +
                   "' (expected sphere, ball/ballend, flat, bullnose, vbit/conical, tapered/snubnose, "
                   "tapered_ball, spheroid or apt)");
}

Tool sphere_tool(double radius) {
  positive("radius", radius);
  Tool tool = with_profile(ToolType::Sphere, {Piece::arc({0, radius}, radius, -0.5 * M_PI, 0.5 * M_PI)},
                           radius, "radius");
  tool.radius = radius;
  return tool;
}

Tool ball_tool(double radius, double length) {
  positive("radius", radius);
  non_negative("length", length);
  std::vector<Piece> pieces{Piece::arc({0, radius}, radius, -0.5 * M_PI, 0.0)};
  if (length > 0.0) pieces.push_back(Piece::segment({radius, radius}, {radius, radius + length}));
  pieces.push_back(Piece::segment({radius, radius + length}, {0, radius + length}));
  Tool tool = with_profile(ToolType::BallEnd, std::move(pieces), 0.0, "length");
  tool.radius = radius;
  tool.length = length;
  return tool;
}

ToolProfile profile_of(const Tool& tool) {
  if (!tool.profile.empty()) return tool.profile;
  if (tool.type == ToolType::Sphere) return sphere_tool(tool.radius).profile;
  if (tool.type == ToolType::BallEnd) return ball_tool(tool.radius, tool.length).profile;
  throw InputError("tool " + std::to_string(tool.number) + " (" + to_string(tool.type) +
                   ") has no profile; build it with the constructors of morph/tool.h");
}

Tool flat_tool(double radius, double length) {
  positive("radius", radius);
  positive("length", length);
  Tool tool =
      with_profile(ToolType::Flat,
                   {Piece::segment({0, 0}, {radius, 0}), Piece::segment({radius, 0}, {radius, length}),
                    Piece::segment({radius, length}, {0, length})},
                   0.0, "length");
  tool.length = length;
  return tool;
}

Tool bullnose_tool(double radius, double corner_radius, double length) {
  positive("radius", radius);
  positive("corner_radius", corner_radius);
  positive("length", length);
  if (corner_radius > radius)
    throw ToolError("corner_radius", "must not exceed the radius " + number_text(radius) + ", got " +
                                         number_text(corner_radius));
  if (corner_radius > length)
    throw ToolError("length", "must be at least the corner radius " + number_text(corner_radius) + ", got " +
                                  number_text(length));
  const double flat = radius - corner_radius;
  std::vector<Piece> pieces;
  if (flat > 0.0) pieces.push_back(Piece::segment({0, 0}, {flat, 0}));
  pieces.push_back(Piece::arc({flat, corner_radius}, corner_radius, -0.5 * M_PI, 0.0));
  if (length > corner_radius) pieces.push_back(Piece::segment({radius, corner_radius}, {radius, length}));
  pieces.push_back(Piece::segment({radius, length}, {0, length}));
  Tool tool = with_profile(ToolType::Bullnose, std::move(pieces), 0.0, "corner_radius");
  tool.radius = radius;
  tool.length = length;
  tool.corner_radius = corner_radius;
  return tool;
}

double cone_height(double radius, double included_angle, double tip_radius) {
  return (radius - tip_radius) / std::tan(0.5 * included_angle * kDegree);
}

double cone_angle(double radius, double height, double tip_radius) {
  return 2.0 * std::atan2(radius - tip_radius, height) / kDegree;
}

Tool conical_tool(double radius, double included_angle, double length, double tip_radius) {
  positive("radius", radius);
  angle_in("angle", included_angle, 0.0, true, 180.0,
           "an included angle between 0 and 180 degrees (exclusive)");
  positive("length", length);
  non_negative("tip_radius", tip_radius);
  if (!(tip_radius < radius))
    throw ToolError("tip_radius", "must be less than the radius " + number_text(radius) + ", got " +
                                      number_text(tip_radius));
  double height = cone_height(radius, included_angle, tip_radius);
  // A length equal to the cone's height up to rounding is the cone alone (CAMotics' conical).
  if (std::abs(length - height) <= 1e-12 * std::max(length, height)) height = length;
  if (length < height)
    throw ToolError("length", "must be at least the cone's height " + number_text(height) + " (radius " +
                                  number_text(radius) + ", angle " + number_text(included_angle) + "), got " +
                                  number_text(length));
  Tool tool = with_profile(ToolType::Conical, cone_pieces(tip_radius, radius, height, length), 0.0, "angle");
  tool.radius = radius;
  tool.length = length;
  tool.angle = included_angle;
  tool.tip_radius = tip_radius;
  return tool;
}

Tool tapered_tool(double tip_radius, double radius, double length) {
  non_negative("tip_radius", tip_radius);
  positive("radius", radius);
  positive("length", length);
  if (!(radius > tip_radius))
    throw ToolError("radius", "must exceed the tip radius " + number_text(tip_radius) +
                                  " (a taper opens upward), got " + number_text(radius));
  Tool tool = with_profile(ToolType::Tapered, cone_pieces(tip_radius, radius, length, length), 0.0, "radius");
  tool.radius = radius;
  tool.length = length;
  tool.tip_radius = tip_radius;
  tool.angle = std::atan2(radius - tip_radius, length) / kDegree;
  return tool;
}

double tapered_ball_angle(double ball_radius, double radius, double length) {
  // The side line at taper a, tangent to the ball, reaches r = radius at h = length when
  // radius cos(a) - (length - ball_radius) sin(a) = ball_radius.
  const double b = length - ball_radius;
  return (std::acos(std::clamp(ball_radius / std::hypot(radius, b), -1.0, 1.0)) - std::atan2(b, radius)) /
         kDegree;
}

Tool tapered_ball_tool(double ball_radius, double taper_angle, double length) {
  positive("tip_radius", ball_radius);
  angle_in("angle", taper_angle, 0.0, false, 90.0, "a taper per side of at least 0 and below 90 degrees");
  positive("length", length);
  const double a = taper_angle * kDegree;
  const Vector2d tangent(ball_radius * std::cos(a), ball_radius * (1.0 - std::sin(a)));
  if (!(length > tangent.y()))
    throw ToolError("length", "must exceed the height " + number_text(tangent.y()) +
                                  " where the taper leaves the ball, got " + number_text(length));
  const double top = tangent.x() + (length - tangent.y()) * std::tan(a);
  Tool tool =
      with_profile(ToolType::TaperedBall,
                   {Piece::arc({0, ball_radius}, ball_radius, -0.5 * M_PI, -a),
                    Piece::segment(tangent, {top, length}), Piece::segment({top, length}, {0, length})},
                   0.0, "angle");
  tool.length = length;
  tool.tip_radius = ball_radius;
  tool.angle = taper_angle;
  return tool;
}

Tool spheroid_tool(double radius, double height) {
  positive("radius", radius);
  positive("length", height);
  const Vector2d centre(0, 0.5 * height), radii(radius, 0.5 * height);
  Tool tool = with_profile(
      ToolType::Spheroid,
      {Piece::ellipse(centre, radii, -0.5 * M_PI, 0.0), Piece::ellipse(centre, radii, 0.0, 0.5 * M_PI)}, 0.0,
      "length");
  tool.radius = radius;
  tool.length = height;
  return tool;
}

Tool apt_tool(double diameter, double corner_radius, double alpha, double beta, double height, double check_e,
              double check_f) {
  positive("diameter", diameter);
  non_negative("corner_radius", corner_radius);
  angle_in("alpha", alpha, 0.0, false, 90.0, "at least 0 and below 90 degrees");
  angle_in("beta", beta, -90.0, true, 90.0, "between -90 and 90 degrees (exclusive)");
  positive("height", height);
  if (!(alpha + beta < 90.0))
    throw ToolError("beta",
                    "alpha + beta must be below 90 degrees (the side must rise above the bottom), got " +
                        number_text(alpha + beta));
  const double a = alpha * kDegree, b = beta * kDegree;
  const Vector2d corner(0.5 * diameter, 0.5 * diameter * std::tan(a));
  const Vector2d side(std::sin(b), std::cos(b));
  // The corner circle's centre: at corner_radius inside both the bottom line (through the tip)
  // and the side line (through `corner`).
  const Vector2d n1(-std::sin(a), std::cos(a)), n2(-std::cos(b), std::sin(b));
  const double rhs1 = corner_radius, rhs2 = corner_radius + n2.dot(corner);
  const double det = n1.x() * n2.y() - n1.y() * n2.x();  // sin(alpha + beta - 90) != 0
  const Vector2d centre((rhs1 * n2.y() - n1.y() * rhs2) / det, (n1.x() * rhs2 - rhs1 * n2.x()) / det);
  const Vector2d t1 = centre - corner_radius * n1, t2 = centre - corner_radius * n2;
  if (t1.x() < -1e-12 * diameter)
    throw ToolError("corner_radius", "is too large for the diameter " + number_text(diameter) +
                                         " and alpha: the corner would cross the axis");
  if (!(t2.y() < height))
    throw ToolError("height", "must exceed " + number_text(t2.y()) + ", where the side begins, got " +
                                  number_text(height));
  const double top = t2.x() + (height - t2.y()) * std::tan(b);
  if (!(top >= 0.0))
    throw ToolError("beta", "the side reaches the axis below the height " + number_text(height));
  const double scale = std::max(diameter, height);
  for (auto [field, given, actual] : {std::tuple<const char*, double, double>{"e", check_e, centre.x()},
                                      std::tuple<const char*, double, double>{"f", check_f, centre.y()}})
    if (!std::isnan(given) && !(std::abs(given - actual) <= 1e-6 * scale))
      throw ToolError(field, std::string("must be ") + number_text(actual) +
                                 " for this diameter, corner radius, alpha and beta, got " +
                                 number_text(given));
  std::vector<Piece> pieces;
  if (t1.x() > 1e-12 * diameter) pieces.push_back(Piece::segment({0, 0}, t1));
  if (corner_radius > 0.0) pieces.push_back(Piece::arc(centre, corner_radius, a - 0.5 * M_PI, -b));
  pieces.push_back(Piece::segment(t2, {top, height}));
  if (top > 0.0) pieces.push_back(Piece::segment({top, height}, {0, height}));
  Tool tool = with_profile(ToolType::Apt, std::move(pieces), 0.0, "beta");
  tool.length = height;
  tool.corner_radius = corner_radius;
  tool.apt_diameter = diameter;
  tool.apt_e = centre.x();
  tool.apt_f = centre.y();
  tool.apt_alpha = alpha;
  tool.apt_beta = beta;
  return tool;
}

std::string describe(const Tool& tool) {
  std::ostringstream out;
  out.precision(6);
  out << to_string(tool.type) << " diameter "
      << (tool.type == ToolType::Apt ? tool.apt_diameter : 2.0 * tool.radius);
  switch (tool.type) {
    case ToolType::Sphere:
      break;
    case ToolType::BallEnd:
      out << ", length " << tool.length << " above the ball's centre";
      break;
    case ToolType::Bullnose:
      out << ", corner radius " << tool.corner_radius << ", length " << tool.length;
      break;
    case ToolType::Conical:
      out << ", angle " << tool.angle << " deg";
      if (tool.tip_radius > 0.0) out << ", tip diameter " << 2.0 * tool.tip_radius;
      out << ", length " << tool.length;
      break;
    case ToolType::Tapered:
      out << ", tip diameter " << 2.0 * tool.tip_radius << ", taper " << tool.angle << " deg/side, length "
          << tool.length;
      break;
    case ToolType::TaperedBall:
      out << " at the top, tip ball radius " << tool.tip_radius << ", taper " << tool.angle
          << " deg/side, length " << tool.length;
      break;
    case ToolType::Apt:
      out << ", corner radius " << tool.corner_radius << ", e " << tool.apt_e << ", f " << tool.apt_f
          << ", alpha " << tool.apt_alpha << ", beta " << tool.apt_beta << ", height " << tool.length;
      break;
    case ToolType::Flat:
    case ToolType::Spheroid:
      out << ", length " << tool.length;
      break;
  }
  return out.str();
}

double tool_signed_distance(const Tool& tool, const Eigen::Vector3d& tool_point, const Eigen::Vector3d& p) {
  switch (tool.type) {
    case ToolType::Sphere:
      return (p - tool_point).norm() - tool.radius;
    case ToolType::BallEnd: {
      // Union of the tip ball and the body cylinder: exact outside the tool and inside below the
      // ball's centre; inside above it, where the ball's upper half is not boundary, a little
      // shallower than the profile's exact value (by less than (R - r) - (R - |q|) <= z^2 / (2 r)).
      // The generator's seams and the ball-end sweeps are built on this value, so it stays.
      const Eigen::Vector3d q = p - (tool_point + Eigen::Vector3d(0, 0, tool.radius));
      const double ball = q.norm() - tool.radius;
      const double body = detail::capped_cylinder_distance(q, tool.radius, 0.0, tool.length);
      return std::min(ball, body);
    }
    default:
      break;
  }
  if (tool.profile.empty())
    throw InputError("tool " + std::to_string(tool.number) + " ('" + to_string(tool.type) +
                     "') has no profile; build it with the constructors of morph/tool.h");
  const Eigen::Vector3d q = p - tool_point;
  return tool.profile.signed_distance(std::sqrt(q.x() * q.x() + q.y() * q.y()),
                                      q.z() + tool.profile.point_height());
}

ToolExtent tool_extent(const Tool& tool) {
  switch (tool.type) {
    case ToolType::Sphere:
      return {tool.radius, tool.radius, tool.radius};
    case ToolType::BallEnd:
      return {0.0, tool.radius + tool.length, tool.radius};
    default:
      break;
  }
  if (tool.profile.empty())
    throw InputError("tool " + std::to_string(tool.number) + " ('" + to_string(tool.type) +
                     "') has no profile; build it with the constructors of morph/tool.h");
  const double h = tool.profile.point_height();
  return {h, tool.profile.height() - h, tool.profile.radius()};
}

}  // namespace morph
