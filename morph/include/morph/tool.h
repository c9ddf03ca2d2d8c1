// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file tool.h
/// Tools (the structuring element B): solids of revolution about +z, cutting with their lower
/// end, each given by a convex profile (tool_profile.h). The named shapes below are constructors
/// of that one type; they check their sizes and throw ToolError naming the field at fault.
#include <morph/tool_profile.h>

#include <Eigen/Core>
#include <cmath>
#include <string>

namespace morph {

enum class ToolType {
  Sphere,       ///< ball of `radius` centred on the tool point (the paper's B)
  BallEnd,      ///< ball-end mill: hemispherical tip + cylinder; the tool point is the tip
  Flat,         ///< flat end mill (CAMotics "cylindrical")
  Bullnose,     ///< corner-radius end mill
  Conical,      ///< V-bit / engraving cone, optionally with a flat tip and a shank above
  Tapered,      ///< truncated cone, flat tip (CAMotics "snubnose")
  TaperedBall,  ///< ball tip with a tangent conical taper above
  Spheroid,     ///< ellipsoid standing on its tip (CAMotics "spheroid")
  Apt,          ///< the APT 7-parameter cutter
};

/// "sphere", "ballend", "flat", "bullnose", "conical", "tapered", "tapered_ball", "spheroid", "apt".
const char* to_string(ToolType type);
/// Parses the names above and the aliases "ball" (ballend), "vbit" (conical) and "snubnose"
/// (tapered); throws InputError naming `where` for an unknown name.
ToolType tool_type_from_string(const std::string& name, const std::string& where);

/// A tool in job units. Build one with the constructors below; the generator and the closed-form
/// fast paths read `type`, `radius` and `length` directly, everything else reads `profile`.
struct Tool {
  int number = 0;
  ToolType type = ToolType::Sphere;
  double radius = 0.0;         ///< largest radius of the tool (half its cutting diameter)
  double length = 0.0;         ///< BallEnd: cylinder above the hemisphere's centre (what the
                               ///< generator reads); every other shape but Sphere: height of the
                               ///< tool above its tip
  double corner_radius = 0.0;  ///< Bullnose, Apt: radius of the corner arc
  double angle = 0.0;          ///< degrees. Conical: included angle; Tapered, TaperedBall: taper per side
  double tip_radius = 0.0;     ///< Conical, Tapered: radius of the flat tip; TaperedBall: ball radius
  /// Apt: its diameter (where bottom and side meet, extended), the corner centre (e from the
  /// axis, f above the tip) and the angles in degrees.
  double apt_diameter = 0.0, apt_e = 0.0, apt_f = 0.0, apt_alpha = 0.0, apt_beta = 0.0;
  /// Tool length offset of a tool table (LinuxCNC .tbl Z column), job units; read by G43.
  double length_offset = 0.0;
  std::string description;
  /// The exact shape. Empty only for a Sphere or BallEnd assembled field by field (tests and
  /// older code), which the closed forms handle from `radius` and `length`.
  ToolProfile profile;

  /// A sphere or a ball end: the shapes whose sweep distances have the capsule's closed forms
  /// (sweep_distance.h), also without a profile.
  bool sphere_or_ball_end() const { return type == ToolType::Sphere || type == ToolType::BallEnd; }
};

/// Named shapes, sizes in job units, angles in degrees. Every size must be finite; each throws
/// ToolError("radius: must be greater than 0, got -1") naming its parameter.
Tool sphere_tool(double radius);

/// The tool's profile; for a sphere or ball end assembled field by field (no profile, Tool::profile),
/// the one its radius and length make. Throws InputError for any other tool without a profile.
ToolProfile profile_of(const Tool& tool);
/// `length`: the cylinder above the hemisphere's centre (>= 0); the tool is radius + length tall.
Tool ball_tool(double radius, double length);
Tool flat_tool(double radius, double length);
/// 0 < corner_radius <= radius, corner_radius <= length.
Tool bullnose_tool(double radius, double corner_radius, double length);
/// A cone of `included_angle` in (0, 180) from a flat tip of `tip_radius` (>= 0, < radius) out to
/// `radius`, then a cylinder of `radius` up to `length` (>= the cone's height).
Tool conical_tool(double radius, double included_angle, double length, double tip_radius = 0.0);
/// Height of that cone: (radius - tip_radius) / tan(angle / 2).
double cone_height(double radius, double included_angle, double tip_radius = 0.0);
/// Included angle of a cone from tip_radius to radius over `height` (the inverse of cone_height).
double cone_angle(double radius, double height, double tip_radius = 0.0);
/// Truncated cone from `tip_radius` (>= 0) at the tip to `radius` (> tip_radius) at `length`.
Tool tapered_tool(double tip_radius, double radius, double length);
/// Ball of `ball_radius` at the tip, then a cone tangent to it opening at `taper_angle` per side
/// ([0, 90)) up to `length` (> ball_radius).
Tool tapered_ball_tool(double ball_radius, double taper_angle, double length);
/// The taper per side that brings a tapered ball of `ball_radius` to `radius` at `length`.
double tapered_ball_angle(double ball_radius, double radius, double length);
/// Ellipsoid of radii (radius, radius, height / 2) whose lowest point is the tip.
Tool spheroid_tool(double radius, double height);
/// APT: the bottom rises from the tip at `alpha` above horizontal ([0, 90)); the side leans out
/// at `beta` from vertical ((-90, 90), alpha + beta < 90); extended, they meet at diameter / 2.
/// A corner arc of `corner_radius` (>= 0) is tangent to both; the tool is `height` tall. The
/// corner's centre (e from the axis, f above the tip) follows; `check_e`/`check_f` (NaN: not
/// given) are compared with it and a mismatch names the field.
Tool apt_tool(double diameter, double corner_radius, double alpha, double beta, double height,
              double check_e = std::nan(""), double check_f = std::nan(""));

/// "flat D6 L20", "bullnose D10 r2 L30", ...: the shape and its catalogue sizes in job units.
std::string describe(const Tool& tool);

/// Exact signed distance (job units, negative inside) from `p` to the tool placed with its tool
/// point at `tool_point`: the profile's 2D distance in p's meridian half-plane.
double tool_signed_distance(const Tool& tool, const Eigen::Vector3d& tool_point, const Eigen::Vector3d& p);

/// Offset from the tool point to the lowest and highest tool points along z, and the radius of
/// the tool's bounding cylinder: used to bound sweeps.
struct ToolExtent {
  double below = 0.0;  ///< how far the tool reaches below the tool point
  double above = 0.0;  ///< how far above
  double radius = 0.0;
};
ToolExtent tool_extent(const Tool& tool);

}  // namespace morph
