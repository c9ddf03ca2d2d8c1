// SPDX-License-Identifier: Apache-2.0
// Generator 2's spike (docs: ../shared/design/generator2.md §4, issue 18): on bear.nc at 0.01 mm,
// build every move's sweep polytope, cull the facets proven outside the stock or inside another
// sweep, count the survivors and the planes that can cut them, and time a naive floating-point
// clipping of each survivor by the union of its cutters, all on one core; then morph::erode on
// the same job (its own threads) for comparison, in the same run.
//
// Culling uses the exact sweep distance (morph/sweep_distance.h) with proofs: the polytope P_j is
// within b (its deviation) of the exact sweep K_j, both convex, so d_j(c) < -(ρ + b) puts a ball
// of radius ρ about c inside P_j, and d_j(c) > ρ + b puts it outside. Facets are first grouped in
// clusters (a 1 mm grid of their centres) so that most proofs are made once per cluster, and each
// cutter's planes are reduced per cluster to those within the cluster's radius of its centre.
//
//   build/tests/bench/bench_morph --benchmark_filter=Generator2Spike
// Times are this thread's CPU seconds (erode's: its own wall-clock total, on 2 threads).
#include <benchmark/benchmark.h>
#include <morph/aabb_tree.h>
#include <morph/erode.h>
#include <morph/error_budget.h>
#include <morph/gcode.h>
#include <morph/sweep_distance.h>
#include <morph/sweep_polytope.h>
#include <morph/tool_polytope.h>

#include "generator2_bench_support.h"

#include <cmath>
#include <ctime>
#include <deque>
#include <fstream>
#include <map>
#include <memory>
#include <unordered_map>

namespace {

using namespace generator2_bench;

// A surviving facet piece (inside the stock) and the planes of each sweep that may cut it.
struct Survivor {
  Polygon polygon;
  std::vector<std::vector<Plane>> cutters;
};

struct Counts {
  double facets = 0, outside_stock = 0, inside_by_cluster = 0, inside = 0, survivors = 0, clusters = 0;
  double cutters = 0, cutter_planes = 0, planes_scanned = 0, ties = 0, pieces = 0, kept_area = 0;
  double clip_seconds = 0;
};

void clip(const Survivor& survivor, Counts& counts);

// A sweep as a cutter: its planes and an index of its faces' boxes. Only the planes of faces
// meeting a facet shape facet ∩ P_j (where a plane runs past its face inside the facet, the
// neighbouring face meets the facet too); if no face meets it, the facet is wholly in or out.
struct Cutter {
  std::vector<Plane> planes;
  morph::AabbTree faces;
};

// Cutters built on demand from the moves and kept in a bounded first-in first-out cache
// (a 1.6 mm ball's sweep with its index is about 100 kB).
class CutterCache {
 public:
  CutterCache(const morph::SweepPolytopeBuilder& sweep_of, const std::vector<morph::Move>& moves)
      : sweep_of_(sweep_of), moves_(moves) {}
  const Cutter& get(std::size_t j) {
    auto found = cache_.find(j);
    if (found != cache_.end()) return *found->second;
    if (order_.size() >= kCapacity) {
      cache_.erase(order_.front());
      order_.pop_front();
    }
    const morph::ConvexPolytope sweep = sweep_of_(moves_[j].start, moves_[j].end);
    auto cutter = std::make_unique<Cutter>();
    std::vector<Eigen::AlignedBox3d> boxes;
    for (const morph::PolytopeFacet& f : sweep.facets) {
      cutter->planes.push_back({f.normal, f.offset});
      Eigen::AlignedBox3d box;
      for (int v : f.loop) box.extend(sweep.vertices[v]);
      boxes.push_back(box);
    }
    cutter->faces = morph::AabbTree(std::move(boxes));
    ++built;
    order_.push_back(j);
    return *(cache_[j] = std::move(cutter));
  }
  double built = 0;

 private:
  static constexpr std::size_t kCapacity = 4000;
  const morph::SweepPolytopeBuilder& sweep_of_;
  const std::vector<morph::Move>& moves_;
  std::unordered_map<std::size_t, std::unique_ptr<Cutter>> cache_;
  std::deque<std::size_t> order_;
};

// Facets of `sweep` inside `stock`, clustered, proven away or kept with their cutters' planes
// and clipped at once (clip() timed on its own).
void cull_sweep(std::size_t i, const morph::ConvexPolytope& sweep, const Eigen::AlignedBox3d& stock,
                const std::vector<morph::Move>& moves, const morph::Tool& tool, const morph::AabbTree& tree,
                CutterCache& cutters, double deviation, Counts& counts) {
  const Plane stock_planes[6] = {
      {-Vector3d::UnitX(), -stock.min().x()}, {Vector3d::UnitX(), stock.max().x()},
      {-Vector3d::UnitY(), -stock.min().y()}, {Vector3d::UnitY(), stock.max().y()},
      {-Vector3d::UnitZ(), -stock.min().z()}, {Vector3d::UnitZ(), stock.max().z()}};
  struct Piece {
    Polygon polygon;
    Vector3d centre;
    double radius;
  };
  std::map<std::array<long, 3>, std::vector<Piece>> clusters;
  Polygon above, below;
  for (const morph::PolytopeFacet& facet : sweep.facets) {
    ++counts.facets;
    Polygon polygon;
    for (int v : facet.loop) polygon.push_back(sweep.vertices[v]);
    for (const Plane& plane : stock_planes) {
      split(polygon, plane, above, below);
      polygon.swap(below);
      if (polygon.empty()) break;
    }
    if (polygon.empty() || area(polygon) == 0.0) {
      ++counts.outside_stock;
      continue;
    }
    Vector3d centre = Vector3d::Zero();
    for (const Vector3d& p : polygon) centre += p;
    centre /= static_cast<double>(polygon.size());
    double radius = 0.0;
    for (const Vector3d& p : polygon) radius = std::max(radius, (p - centre).norm());
    const std::array<long, 3> key{std::lround(std::floor(centre.x())), std::lround(std::floor(centre.y())),
                                  std::lround(std::floor(centre.z()))};
    clusters[key].push_back({std::move(polygon), centre, radius});
  }
  const double margin = deviation + kOnPlane;
  for (auto& [key, pieces] : clusters) {
    ++counts.clusters;
    Vector3d centre = Vector3d::Zero();
    for (const Piece& piece : pieces) centre += piece.centre;
    centre /= static_cast<double>(pieces.size());
    double radius = 0.0;
    for (const Piece& piece : pieces)
      radius = std::max(radius, (piece.centre - centre).norm() + piece.radius);
    const Eigen::AlignedBox3d box(centre.array() - radius - margin, centre.array() + radius + margin);
    std::vector<std::size_t> near;
    bool hidden = false;
    tree.for_each_overlapping(box, [&](std::size_t j) {
      if (hidden || j == i) return;
      const double d = morph::swept_signed_distance(tool, moves[j].start, moves[j].end, centre);
      if (d < -(radius + margin)) hidden = true;
      if (d <= radius + margin) near.push_back(j);
    });
    if (hidden) {
      counts.inside_by_cluster += static_cast<double>(pieces.size());
      continue;
    }
    for (Piece& piece : pieces) {
      Survivor survivor;
      bool inside = false;
      Eigen::AlignedBox3d piece_box;
      for (const Vector3d& p : piece.polygon) piece_box.extend(p);
      piece_box.min().array() -= kOnPlane;
      piece_box.max().array() += kOnPlane;
      for (std::size_t k = 0; k < near.size() && !inside; ++k) {
        const double d =
            morph::swept_signed_distance(tool, moves[near[k]].start, moves[near[k]].end, piece.centre);
        if (d < -(piece.radius + margin)) inside = true;
        if (d > piece.radius + margin) continue;
        const Cutter& cutter = cutters.get(near[k]);
        std::vector<Plane> cutting;
        cutter.faces.for_each_overlapping(piece_box,
                                          [&](std::size_t f) { cutting.push_back(cutter.planes[f]); });
        counts.planes_scanned += static_cast<double>(cutting.size());
        if (cutting.empty()) {
          // No face of P_j meets the facet: it is wholly inside or wholly outside, which the
          // centre's exact distance settles beyond the deviation, and the planes otherwise.
          if (d < -(deviation + kOnPlane)) inside = true;
          if (std::abs(d) < deviation + kOnPlane && [&] {
                for (const Plane& plane : cutter.planes)
                  if (plane.value(piece.centre) >= -kOnPlane) return false;
                return true;
              }())
            inside = true;
          continue;
        }
        // Of those, the planes that cut this polygon; none if it is on or above one of them.
        std::vector<Plane> splitting;
        bool apart = false;
        for (const Plane& plane : cutting) {
          double lo = 1e300, hi = -1e300;
          for (const Vector3d& p : piece.polygon) {
            const double v = plane.value(p);
            lo = std::min(lo, v);
            hi = std::max(hi, v);
          }
          if (hi <= -kOnPlane) continue;
          if (lo >= -kOnPlane) {
            apart = true;
            if (hi <= kOnPlane) ++counts.ties;
            break;
          }
          splitting.push_back(plane);
        }
        if (!apart && !splitting.empty()) survivor.cutters.push_back(std::move(splitting));
      }
      if (inside) {
        ++counts.inside;
        continue;
      }
      ++counts.survivors;
      counts.cutters += static_cast<double>(survivor.cutters.size());
      for (const auto& cutter : survivor.cutters) counts.cutter_planes += static_cast<double>(cutter.size());
      survivor.polygon = std::move(piece.polygon);
      const double start = thread_seconds();
      clip(survivor, counts);
      counts.clip_seconds += thread_seconds() - start;
    }
  }
}

// The naive clipping of a survivor by the union of its cutters.
void clip(const Survivor& survivor, Counts& counts) {
  generator2_bench::clip(survivor.polygon, survivor.cutters, counts.pieces, counts.kept_area);
}

void BM_Generator2SpikeBear(benchmark::State& state) {
  const std::string path = std::string(MORPHMILL_SHARED_DIR) + "/gcode/bear.nc";
  if (!std::ifstream(path)) {
    state.SkipWithError(("missing " + path).c_str());
    return;
  }
  const morph::Job job = bear_job(path);
  const morph::Tool& tool = job.tools.at(1);
  std::vector<morph::Move> moves = job.paths.front().moves;
  if (state.range(0) > 0 && static_cast<std::size_t>(state.range(0)) < moves.size())
    moves.resize(state.range(0));
  for (const morph::Move& m : moves)
    if (m.is_arc()) {
      state.SkipWithError("the spike takes straight moves only");
      return;
    }
  const double deviation = morph::error_budget(job, job.tolerance).tool;  // the tool's share
  for (auto _ : state) {
    Counts counts;
    double start = thread_seconds();
    const morph::ToolPolytope tool_polytope = morph::tool_polytope(tool.profile, deviation);
    const morph::SweepPolytopeBuilder sweep_of(tool_polytope.polytope);
    std::vector<Eigen::AlignedBox3d> boxes(moves.size());
    for (std::size_t i = 0; i < moves.size(); ++i) boxes[i] = sweep_of(moves[i].start, moves[i].end).bounds();
    const morph::AabbTree tree(boxes);
    const double build = thread_seconds() - start;

    start = thread_seconds();
    CutterCache cutters(sweep_of, moves);
    for (std::size_t i = 0; i < moves.size(); ++i)
      cull_sweep(i, sweep_of(moves[i].start, moves[i].end), job.stock.box, moves, tool, tree, cutters,
                 deviation, counts);
    const double clipping = counts.clip_seconds, cull = thread_seconds() - start - clipping;

    morph::Job cut = job;
    cut.paths.front().moves = moves;
    const morph::ErodeResult generated = morph::erode(cut);
    auto& c = state.counters;
    c["moves"] = static_cast<double>(moves.size());
    c["tool_facets"] = static_cast<double>(tool_polytope.polytope.facets.size());
    c["sweep_facets"] = counts.facets;
    c["outside_stock"] = counts.outside_stock;
    c["inside_by_cluster"] = counts.inside_by_cluster;
    c["inside_by_facet"] = counts.inside;
    c["survivors"] = counts.survivors;
    c["clusters"] = counts.clusters;
    c["cutters_per_survivor"] = counts.cutters / std::max(1.0, counts.survivors);
    c["cutting_planes_per_survivor"] = counts.cutter_planes / std::max(1.0, counts.survivors);
    c["face_planes_found"] = counts.planes_scanned;
    c["cutters_built"] = cutters.built;
    c["float_ties"] = counts.ties;
    c["pieces_out"] = counts.pieces;
    c["kept_area_mm2"] = counts.kept_area;
    c["erode_sweep_area_mm2"] = sweep_area(generated);
    c["s_build_1core"] = build;
    c["s_cull_1core"] = cull;
    c["s_clip_1core"] = clipping;
    c["s_projected_2core"] = 0.5 * (build + cull + clipping);
    c["s_erode"] = generated.stats.seconds_total;
  }
}
// Arg: the first N moves of bear (0: all 15k).
BENCHMARK(BM_Generator2SpikeBear)->Arg(100)->Arg(1000)->Arg(0)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
