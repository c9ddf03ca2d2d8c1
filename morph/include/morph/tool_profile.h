// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file tool_profile.h
/// The shape of every tool: a convex profile in the half-plane (r, h) -- r the distance from the
/// tool axis, h the height above the tool's tip, both in job units -- made of line segments,
/// circular arcs and (for CAMotics' spheroid) quarter ellipses, running from the axis at the
/// bottom out and up to the axis at the top. Revolved about the axis it is the tool's solid; the
/// axis closes it. The exact signed distance of the solid is the 2D signed distance to the
/// profile, because the nearest point of a solid of revolution lies in the point's own meridian
/// half-plane.
#include <morph/exceptions.h>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace morph {

/// A bad tool definition: the message starts with the field at fault ("corner_radius: ..."),
/// which `field()` also gives, so a job reader can put it after the tool's JSON path.
class ToolError : public InputError {
 public:
  ToolError(const std::string& field, const std::string& problem)
      : InputError(field + ": " + problem), field_(field), problem_(problem) {}
  const std::string& field() const { return field_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string field_, problem_;
};

/// One piece of a profile, from its lower end `from` to its upper end `to` (points (r, h)).
struct ProfilePiece {
  enum class Kind {
    Segment,  ///< straight from `from` to `to`
    Arc,      ///< circle of radius radii.x() about `centre`, turning counter-clockwise
    Ellipse,  ///< quarter of the axis-aligned ellipse of semi-axes `radii` (along r, along h)
              ///< about `centre`, counter-clockwise, within one quadrant of it
  };
  Kind kind = Kind::Segment;
  Eigen::Vector2d from = Eigen::Vector2d::Zero(), to = Eigen::Vector2d::Zero();
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  Eigen::Vector2d radii = Eigen::Vector2d::Zero();
  double angle0 = 0.0, angle1 = 0.0;  ///< Arc, Ellipse: (parametric) angles of `from` and `to`, radians

  static ProfilePiece segment(const Eigen::Vector2d& from, const Eigen::Vector2d& to);
  static ProfilePiece arc(const Eigen::Vector2d& centre, double radius, double from_angle, double to_angle);
  static ProfilePiece ellipse(const Eigen::Vector2d& centre, const Eigen::Vector2d& radii, double from_angle,
                              double to_angle);
};

/// A validated convex profile. Heights start at 0 (the tip); the tool point is `point_height`
/// above the tip (0 for end mills, the radius for the paper's sphere).
class ToolProfile {
 public:
  ToolProfile() = default;
  /// Checks the chain: it starts on the axis at h = 0 and ends on the axis, each piece starts
  /// where the previous one ends, every piece stays at r >= 0, heights never fall and the chain
  /// only turns left (convex); throws ToolError naming `field` ("profile" for a raw chain).
  ToolProfile(std::vector<ProfilePiece> pieces, double point_height, const std::string& field = "profile");

  bool empty() const { return pieces_.empty(); }
  const std::vector<ProfilePiece>& pieces() const { return pieces_; }
  double point_height() const { return point_height_; }
  double radius() const { return radius_; }  ///< largest r
  double height() const { return height_; }  ///< h of the top

  /// Exact signed distance (negative inside) from the point (r, h), r >= 0, to the solid.
  double signed_distance(double r, double h) const;
  /// Radius of the solid at height h (0 outside [0, height()]).
  double radius_at(double h) const;
  /// Closed forms the tests check sweeps against: the cross-section area through the axis
  /// (2 * integral of r dh) and the volume (pi * integral of r^2 dh), by exact integration of
  /// each piece.
  double section_area() const;
  double volume() const;
  /// One line per piece, for reports ("segment (0,0)-(3,0); arc ...").
  std::string describe() const;

 private:
  std::vector<ProfilePiece> pieces_;
  double point_height_ = 0.0;
  double radius_ = 0.0;
  double height_ = 0.0;
};

namespace detail {
/// Distance from (y0, y1), both >= 0, to the ellipse x0^2/e0^2 + x1^2/e1^2 = 1 (e0, e1 > 0),
/// by bisection on the nearest point's Lagrange parameter to a relative 4e-16 (D. Eberly,
/// "Distance from a point to an ellipse"); unsigned.
double ellipse_quadrant_distance(double e0, double e1, double y0, double y1);
}  // namespace detail

}  // namespace morph
