// SPDX-License-Identifier: Apache-2.0
#pragma once
// Jobs as the generator tests build them: tool 1, one path through the given points (move k from
// point k to point k+1, numbered as G-code line k + 2).
#include <morph/job.h>
#include <morph/tool.h>

#include <vector>

namespace morphmill_test {

inline morph::Job polyline_job(const morph::Stock& stock, const morph::Tool& tool,
                               const std::vector<Eigen::Vector3d>& polyline, double tolerance) {
  morph::Job job;
  job.stock = stock;
  job.tools.emplace(1, tool);
  job.tolerance = tolerance;
  morph::Path path;
  for (std::size_t k = 0; k + 1 < polyline.size(); ++k) {
    morph::Move m;
    m.start = polyline[k];
    m.end = polyline[k + 1];
    m.tool = 1;
    m.line = static_cast<int>(k + 2);
    path.moves.push_back(m);
  }
  job.paths.push_back(path);
  return job;
}

inline morph::Job box_polyline_job(const Eigen::AlignedBox3d& box, const morph::Tool& tool,
                                   const std::vector<Eigen::Vector3d>& polyline, double tolerance) {
  morph::Stock stock;
  stock.type = morph::StockType::Box;
  stock.box = box;
  return polyline_job(stock, tool, polyline, tolerance);
}

/// Stress seed 53, case 2106: a tapered tool (tip 0.682, radius 2.035) six times round a triangle
/// of radius 12.65 at tolerance 0.01, its corners as the campaign drew them (the laps' corners
/// differ in their last digits). Its long moves in general directions have silhouette normals
/// wider than 53 bits on generator 2's grid.
inline morph::Job tapered_triangle_six_times_round() {
  const std::vector<Eigen::Vector3d> corners{
      {0.03570871122111897, -12.64994960021355, 3.021},  {10.937323354767177, 6.355899451160668, 3.021},
      {-10.973032065988294, 6.294050149052889, 3.021},   {0.0357087112211271, -12.64994960021355, 3.021},
      {10.937323354767189, 6.355899451160647, 3.021},    {-10.973032065988292, 6.294050149052891, 3.021},
      {0.035708711221124005, -12.64994960021355, 3.021}, {10.937323354767168, 6.355899451160682, 3.021},
      {-10.97303206598829, 6.294050149052893, 3.021},    {0.03570871122111897, -12.64994960021355, 3.021},
      {10.937323354767177, 6.355899451160668, 3.021},    {-10.973032065988294, 6.294050149052889, 3.021},
      {0.0357087112211271, -12.64994960021355, 3.021},   {10.937323354767189, 6.355899451160647, 3.021},
      {-10.973032065988292, 6.294050149052891, 3.021},   {0.035708711221124005, -12.64994960021355, 3.021},
      {10.937323354767168, 6.355899451160682, 3.021},    {-10.97303206598829, 6.294050149052893, 3.021},
      {0.03570871122111897, -12.64994960021355, 3.021}};
  return box_polyline_job(Eigen::AlignedBox3d(Eigen::Vector3d(-16, -17, 0), Eigen::Vector3d(15, 11, 4.835)),
                          morph::tapered_tool(0.682, 2.035, 11.72), corners, 0.01);
}

}  // namespace morphmill_test
