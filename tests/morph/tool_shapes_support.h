#pragma once
// Every tool shape of morph/tool.h once, in sizes like real cutters (mm), for generator 2's
// per-shape tests.
#include <morph/tool.h>

#include <string>
#include <utility>
#include <vector>

namespace morph_test {

inline std::vector<std::pair<std::string, morph::Tool>> every_tool_shape() {
  return {
      {"sphere", morph::sphere_tool(1.5)},
      {"ballend", morph::ball_tool(1.5875, 10.0)},
      {"flat", morph::flat_tool(3.0, 12.0)},
      {"bullnose", morph::bullnose_tool(5.0, 1.0, 15.0)},
      {"vbit", morph::conical_tool(3.0, 60.0, 12.0)},
      {"vbit_tip", morph::conical_tool(3.0, 90.0, 10.0, 0.5)},
      {"tapered", morph::tapered_tool(0.5, 2.0, 8.0)},
      {"tapered_ball", morph::tapered_ball_tool(1.0, 10.0, 12.0)},
      {"spheroid", morph::spheroid_tool(2.0, 6.0)},
      {"apt", morph::apt_tool(10.0, 1.0, 5.0, 10.0, 15.0)},
  };
}

}  // namespace morph_test
