// SPDX-License-Identifier: Apache-2.0
#include "verify/compare.h"

#include <fmt/format.h>
#include <morph/exceptions.h>
#include <morph/sweep_distance.h>
#include <raytest/surface_query.h>

#include <cmath>

#include "verify/verify.h"  // stats_to_json

namespace morphmill {

raytest::ToleranceBand default_band(const morph::Job& job, double low, double high) {
  if (low != 0.0 || high != 0.0) return {low, high};
  return {-5.0 * job.tolerance, 5.0 * job.tolerance};
}

std::string provenance_text(const morph::FaceTag& tag) {
  if (tag.kind == morph::PatchKind::Unknown) return "-";
  if (tag.kind == morph::PatchKind::StockFace || tag.kind == morph::PatchKind::CutSurface)
    return fmt::format("{} {}", morph::to_string(tag.kind), tag.source);
  if (tag.source < 0) return fmt::format("{} (stock)", morph::to_string(tag.kind));
  return fmt::format("{} move {} (line {})", morph::to_string(tag.kind), tag.source, tag.line);
}

DesignComparison compare_with_design(const morph::Job& job, const morph::TriangleMesh& machined,
                                     const morph::TriangleMesh& design, const CompareOptions& options) {
  const raytest::ToleranceBand band = options.band;
  if (band.empty() || band.low > 0 || band.high < 0 || !std::isfinite(band.low) || !std::isfinite(band.high))
    throw morph::InputError(fmt::format(
        "compare: the band must satisfy low <= 0 <= high, not both 0 (got {}, {})", band.low, band.high));
  if (machined.empty()) throw morph::InputError("compare: the machined surface is empty");
  if (design.empty()) throw morph::InputError("compare: the design mesh has no triangles");
  DesignComparison out;
  out.band = band;
  out.machined_triangles = machined.triangle_count();
  out.design_triangles = design.triangle_count();
  Eigen::AlignedBox3d box;
  for (const auto& v : machined.vertices) box.extend(v);
  out.resolution = options.resolution > 0 ? options.resolution
                                          : std::min(box.diagonal().norm() / 400.0, band.high - band.low);
  if (!(out.resolution > 0)) throw morph::InputError("compare: the resolution must be positive");

  const raytest::SurfaceQuery design_query(design), machined_query(machined);
  raytest::DeviationOptions deviation;
  deviation.mode = raytest::DeviationMode::Signed;
  deviation.sampling.face_samples = options.face_samples;
  deviation.sampling.seed = options.seed;
  deviation.stats.band = band;
  out.machined_to_design = raytest::measure_one_sided(machined, design_query, deviation).stats;
  raytest::OneSidedDeviation design_side = raytest::measure_one_sided(design, machined_query, deviation);
  for (double& v : design_side.values) v = -v;  // read as the machined surface relative to the design
  out.design_to_machined = raytest::compute_stats(design_side.values, deviation.stats);

  out.refined = raytest::refine_long_edges(machined, out.resolution);
  out.point_values =
      raytest::vertex_deviation(out.refined.mesh, design_query, raytest::DeviationMode::Signed);
  out.per_point = raytest::compute_stats(out.point_values, deviation.stats);
  const std::vector<raytest::DeviationRegion> regions =
      raytest::find_regions(out.refined.mesh, out.point_values, band);

  const morph::ErosionField field(job);
  const std::vector<const morph::Move*> moves = job.moves();
  std::vector<const morph::Path*> path_of;
  for (const morph::Path& path : job.paths)
    for (std::size_t i = 0; i < path.moves.size(); ++i) path_of.push_back(&path);
  for (const raytest::DeviationRegion& region : regions) {
    (region.kind == raytest::DeviationClass::Gouge ? out.gouge_regions : out.excess_regions)++;
    if (out.regions.size() >= options.max_regions) continue;
    DesignRegion r;
    r.region = region;
    r.nearest_distance = field.sweep_distance(region.location, &r.nearest_move);
    if (r.nearest_move >= 0 && static_cast<std::size_t>(r.nearest_move) < moves.size()) {
      r.nearest_line = moves[r.nearest_move]->line;
      r.nearest_source = path_of[r.nearest_move]->source;
    }
    out.regions.push_back(std::move(r));
  }
  return out;
}

nlohmann::json comparison_to_json(const DesignComparison& c, const morph::Job& job) {
  nlohmann::json j;
  j["sign_convention"] = raytest::kSignConvention;
  j["units"] = morph::to_string(job.units);
  j["band"] = {{"low", c.band.low}, {"high", c.band.high}};
  j["resolution"] = c.resolution;
  j["triangles"] = {{"machined", c.machined_triangles},
                    {"design", c.design_triangles},
                    {"machined_refined", c.refined.mesh.triangle_count()}};
  j["within_band"] = c.within_band();
  j["machined_to_design"] = stats_to_json(c.machined_to_design);
  j["design_to_machined"] = stats_to_json(c.design_to_machined);
  j["per_point"] = stats_to_json(c.per_point);
  j["region_counts"] = {{"gouge", c.gouge_regions}, {"excess", c.excess_regions}};
  j["regions"] = nlohmann::json::array();
  for (const DesignRegion& r : c.regions) {
    nlohmann::json sources = nlohmann::json::array();
    for (const raytest::RegionSource& s : r.region.sources)
      sources.push_back({{"patch_kind", morph::to_string(s.tag.kind)},
                         {"move", s.tag.source},
                         {"line", s.tag.line},
                         {"worst", s.worst}});
    const auto& b = r.region.bounds;
    j["regions"].push_back(
        {{"kind", raytest::to_string(r.region.kind)},
         {"area", r.region.area},
         {"depth", std::abs(r.region.worst)},
         {"worst", r.region.worst},
         {"location", {r.region.location.x(), r.region.location.y(), r.region.location.z()}},
         {"bounds",
          {{"min", {b.min().x(), b.min().y(), b.min().z()}},
           {"max", {b.max().x(), b.max().y(), b.max().z()}}}},
         {"points", r.region.vertices},
         {"made_by", sources},
         {"nearest_move",
          {{"move", r.nearest_move},
           {"line", r.nearest_line},
           {"source", r.nearest_source},
           {"distance", r.nearest_distance}}}});
  }
  return j;
}

}  // namespace morphmill
