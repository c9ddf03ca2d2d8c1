#include <morph/exceptions.h>
#include <morph/tool.h>

#include <morph/convex_minimum.h>

#include <algorithm>
#include <cmath>

namespace morph {

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
  }
  return "unknown";
}

ToolType tool_type_from_string(const std::string& name, const std::string& where) {
  for (ToolType t :
       {ToolType::Sphere, ToolType::BallEnd, ToolType::Flat, ToolType::Bullnose, ToolType::Conical})
    if (name == to_string(t)) return t;
  throw InputError(where + ": unknown tool type '" + name +
                   "' (expected sphere, ballend, flat, bullnose or conical)");
}

double tool_signed_distance(const Tool& tool, const Eigen::Vector3d& tool_point, const Eigen::Vector3d& p) {
  switch (tool.type) {
    case ToolType::Sphere:
      return (p - tool_point).norm() - tool.radius;
    case ToolType::BallEnd: {
      // Union of the tip ball and the body cylinder; both share the ball's equator, so the union
      // of two convex sets here is convex and min() of their distances is exact outside and
      // inside (the cylinder's bottom disc lies inside the ball).
      const Eigen::Vector3d q = p - (tool_point + Eigen::Vector3d(0, 0, tool.radius));
      const double ball = q.norm() - tool.radius;
      const double body = detail::capped_cylinder_distance(q, tool.radius, 0.0, tool.length);
      return std::min(ball, body);
    }
    default:
      break;
  }
  throw InputError(std::string("tool type '") + to_string(tool.type) +
                   "' is reserved but not implemented yet");
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
  throw InputError(std::string("tool type '") + to_string(tool.type) +
                   "' is reserved but not implemented yet");
}

}  // namespace morph
