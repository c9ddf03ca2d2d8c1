#pragma once
/// \file tool.h
/// Tools (the structuring element B) and their exact signed distance.
#include <Eigen/Core>
#include <string>

namespace morph {

enum class ToolType {
  Sphere,    ///< ball of `radius` centred on the tool point (the paper's B)
  BallEnd,   ///< ball-end mill: hemispherical tip of `radius` + cylinder of `length`, axis +z;
             ///< the tool point is the tip (lowest point)
  Flat,      ///< reserved: flat end mill
  Bullnose,  ///< reserved: corner-radius end mill
  Conical,   ///< reserved: conical / engraving tool
};

const char* to_string(ToolType type);
/// Parses "sphere", "ballend", ...; throws InputError naming `where` for an unknown name.
ToolType tool_type_from_string(const std::string& name, const std::string& where);

/// A tool in job units. BallEnd: the tip hemisphere has centre tip + radius*z; the cylindrical
/// body of `radius` runs from that centre up `length` and is closed by a flat top.
struct Tool {
  int number = 0;
  ToolType type = ToolType::Sphere;
  double radius = 0.0;
  double length = 0.0;         ///< BallEnd: cylinder length above the hemisphere centre
  double corner_radius = 0.0;  ///< reserved (Bullnose)
  double angle = 0.0;          ///< reserved (Conical), degrees
  double tip_radius = 0.0;     ///< reserved (Conical)

  /// True for the tools the generator and reference implement (Sphere, BallEnd).
  bool supported() const { return type == ToolType::Sphere || type == ToolType::BallEnd; }
};

/// Exact signed distance (job units, negative inside) from `p` to the tool placed with its tool
/// point at `tool_point`.
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
