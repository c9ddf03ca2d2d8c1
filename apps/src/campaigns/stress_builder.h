// SPDX-License-Identifier: Apache-2.0
#pragma once
// What every stress family builds a case with: the job's stock, tools and paths (a G-code program
// for arcs), the dimensions' rounding, and the rules that keep a case's known result true.
#include <fmt/format.h>
#include <morph/mesh.h>
#include <morph/tool.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "campaigns/stress_cases.h"

namespace morphmill::stress {

using Eigen::Vector3d;

/// Reference voxels per tool radius: coarse enough for ~1 s per case, fine enough that every
/// gap of kGapInRadii radii spans several voxels.
constexpr double kVoxelsPerRadius = 4.0;
/// Smallest width of a piece or of the material between two cuts, in tool radii.
constexpr double kGapInRadii = 1.5;

/// Rounds a drawn dimension to 1e-3 so job files read well; positions computed from rounded
/// dimensions are written exactly (shortest round-trip form).
inline double round3(double value) {
  return std::round(value * 1000.0) / 1000.0;
}

inline nlohmann::json point_json(const Vector3d& p) {
  return nlohmann::json::array({p.x(), p.y(), p.z()});
}

inline morph::TriangleMesh box_mesh(const Vector3d& lo, const Vector3d& hi) {
  morph::TriangleMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  // Outward, counter-clockwise seen from outside.
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

inline morph::TriangleMesh octahedron_mesh(const Vector3d& centre, double a) {
  morph::TriangleMesh mesh;
  mesh.vertices = {centre + Vector3d(a, 0, 0),  centre + Vector3d(-a, 0, 0), centre + Vector3d(0, a, 0),
                   centre + Vector3d(0, -a, 0), centre + Vector3d(0, 0, a),  centre + Vector3d(0, 0, -a)};
  // One triangle per octant, wound outward.
  for (int sx = 0; sx < 2; ++sx)
    for (int sy = 0; sy < 2; ++sy)
      for (int sz = 0; sz < 2; ++sz) {
        std::uint32_t x = sx ? 1 : 0, y = sy ? 3 : 2, z = sz ? 5 : 4;
        const bool flip = (sx + sy + sz) % 2 == 1;
        mesh.triangles.push_back(flip ? morph::Triangle{x, z, y} : morph::Triangle{x, y, z});
      }
  return mesh;
}

/// Builds one case's job.
class Builder {
 public:
  explicit Builder(StressCase& c) : c_(c) {
    c_.job = {{"units", "mm"}, {"tolerance", 0.01}};
    c_.job["paths"] = nlohmann::json::array();
  }

  void tolerance(double t) { c_.job["tolerance"] = t; }

  // Stocks. `swap` exchanges x and y of everything added afterwards (stock and paths), so one
  // family can cut along either axis.
  void box(const Vector3d& lo, const Vector3d& hi) {
    const Vector3d a = map(lo), b = map(hi);
    c_.job["stock"] = {
        {"type", "box"}, {"min", point_json(a.cwiseMin(b))}, {"max", point_json(a.cwiseMax(b))}};
    stock_volume_ = (hi - lo).prod();
  }
  void box_as_mesh(const Vector3d& lo, const Vector3d& hi) {
    const Vector3d a = map(lo), b = map(hi);
    mesh_stock(box_mesh(a.cwiseMin(b), a.cwiseMax(b)), "box");
  }
  void cylinder(double cx, double cy, double radius, double height) {
    const Vector3d base = map(Vector3d(cx, cy, 0));
    c_.job["stock"] = {{"type", "cylinder"},
                       {"base", point_json(base)},
                       {"axis", {0, 0, 1}},
                       {"radius", radius},
                       {"height", height}};
    stock_volume_ = M_PI * radius * radius * height;
  }
  void mesh_stock(morph::TriangleMesh mesh, const std::string& shape) {
    c_.stock_file = case_name(c_.index) + "_stock_" + shape + ".ply";
    c_.job["stock"] = {{"type", "mesh"}, {"path", c_.stock_file}};
    stock_volume_ = morph::enclosed_volume(mesh);
    c_.stock_mesh = std::move(mesh);
  }

  void tool(bool sphere, double radius, double length) {
    sphere_ = sphere;
    radius_ = radius;
    if (sphere)
      c_.job["tools"] = {{"1", {{"type", "sphere"}, {"radius", radius}}}};
    else
      c_.job["tools"] = {{"1", {{"type", "ballend"}, {"radius", radius}, {"length", length}}}};
    c_.voxel_size = radius / kVoxelsPerRadius;
  }
  /// Tool `number` of any shape, given as its job JSON; `radius` its largest radius. The reference's
  /// voxel follows the smallest tool.
  void tool(int number, const nlohmann::json& json, double radius) {
    if (number == 1 || !c_.job.contains("tools")) c_.job["tools"] = nlohmann::json::object();
    c_.job["tools"][std::to_string(number)] = json;
    if (number == 1) {
      sphere_ = json.at("type") == "sphere";
      radius_ = radius;
    }
    const double voxel = radius / kVoxelsPerRadius;
    c_.voxel_size = number == 1 ? voxel : std::min(c_.voxel_size, voxel);
  }
  bool sphere() const { return sphere_; }
  double radius() const { return radius_; }
  /// Tool point z that puts the tool's lowest point at `z`.
  double tool_z_for_lowest(double z) const { return sphere_ ? z + radius_ : z; }

  void path(const std::vector<Vector3d>& points, int tool = 1) {
    nlohmann::json polyline = nlohmann::json::array();
    for (const auto& p : points) polyline.push_back(point_json(map(p)));
    c_.job["paths"].push_back({{"tool", tool}, {"polyline", polyline}});
  }
  /// The case's G-code program (arcs, helices), written next to the job; coordinates as given
  /// (no swap).
  void gcode(const std::string& program, int tool = 1) {
    c_.gcode_file = case_name(c_.index) + ".nc";
    c_.gcode_text = program;
    c_.job["paths"].push_back({{"tool", tool}, {"gcode", c_.gcode_file}});
  }

  void swap_xy(bool swap) { swap_ = swap; }
  double stock_volume() const { return stock_volume_; }

  void expected_volume(double volume) { c_.expected_volume = volume; }
  void expected_genus(int genus) { c_.expected_genus = genus; }

  void finish(const std::string& variant, int pieces) {
    c_.variant = variant;
    c_.expected_pieces = pieces;
  }

 private:
  Vector3d map(const Vector3d& p) const { return swap_ ? Vector3d(p.y(), p.x(), p.z()) : p; }

  StressCase& c_;
  bool swap_ = false;
  bool sphere_ = false;
  double radius_ = 1.0;
  double stock_volume_ = 0.0;
};

/// Closed forms of the motion families (stress_motions.cpp), for a tool standing on its tip with
/// `depth` (job units) of it below the stock's top: the meridian section below the top (what a
/// level pass removes per unit of its length), the tool's volume below the top, and the volume
/// a vertical plunge to that depth removes (the widest radius up to each height, revolved).
/// Integrals of the profile's radius, to ~1e-9 relative.
double section_below(const morph::Tool& tool, double depth);
double volume_below(const morph::Tool& tool, double depth);
double plunge_volume(const morph::Tool& tool, double depth);

/// A family: draws its choices from the case's random stream and builds the job.
using Family = void (*)(CaseRandom&, Builder&);

/// The motion families (stress_motions.cpp), by name.
const std::vector<std::pair<std::string, Family>>& motion_family_table();

inline double draw_tolerance(CaseRandom& rng) {
  static const double choices[] = {0.01, 0.02, 0.05};
  return choices[rng.integer(0, 2)];
}

}  // namespace morphmill::stress
