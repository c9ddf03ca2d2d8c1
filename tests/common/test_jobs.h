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

}  // namespace morphmill_test
