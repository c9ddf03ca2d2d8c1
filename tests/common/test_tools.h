// SPDX-License-Identifier: Apache-2.0
#pragma once
// Tools as the tests build them: tool number 1, sizes in job units.
#include <morph/tool.h>

namespace morphmill_test {

inline morph::Tool sphere_tool(double radius) {
  morph::Tool t;
  t.number = 1;
  t.type = morph::ToolType::Sphere;
  t.radius = radius;
  return t;
}

inline morph::Tool ballend_tool(double radius, double length) {
  morph::Tool t;
  t.number = 1;
  t.type = morph::ToolType::BallEnd;
  t.radius = radius;
  t.length = length;
  return t;
}

}  // namespace morphmill_test
